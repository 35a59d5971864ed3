// The exact reference (tools/reference/exact_reference.hpp) against closed
// forms: sphere-sphere, capsule-capsule (parallel: a segment difference,
// crossed: a flat one), axis-aligned boxes separated and overlapping, box-
// sphere at a face and a corner, flat and segment hulls, margins; cylinders
// and cones whose closed forms are known (a face or a rim over a plane, side
// by side, an apex 1e-6 over a large face), where the bracket must hold the
// closed form and stay narrow; bad
// input; and agreement with hedra's queries on seeded random polytope pairs.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <exact_reference.hpp>
#include <hedra/collision/query.hpp>
#include <limits>
#include <random>

#include "collision_test_support.hpp"

namespace hedra::collision {
namespace {

using reference::exact_signed_distance;
using reference::ExactResult;
using testing::make_hull;
using testing::random_points;
using testing::random_unit;
using Vec = Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

Pose at(const Vec& t) { return Pose::from_translation(t); }
Pose turned(double angle, const Vec& axis, const Vec& t) {
  return Pose::from_quaternion(Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized())), t);
}

// The witnesses agree with the distance and the normal, and lie on the shapes'
// surfaces (support value along the normal for A, along -normal for B).
void expect_consistent(const ExactResult& r, double scale) {
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_NEAR(r.normal.norm(), 1.0, 1e-12);
  EXPECT_LE((r.point_b - r.point_a - r.distance * r.normal).norm(), 1e-9 * scale);
}

TEST(ExactReference, SphereSphereSeparatedAndOverlapping) {
  const Shape a = Sphere{0.5, 0.0}, b = Sphere{0.25, 0.05};
  const Vec c(0.3, -0.4, 1.2);
  ExactResult r = exact_signed_distance(a, at(Vec(1, 2, 3)), b, at(Vec(1, 2, 3) + c));
  expect_consistent(r, 1);
  EXPECT_NEAR(r.distance, c.norm() - 0.8, 1e-14);
  EXPECT_EQ(r.dimension, 0);
  EXPECT_TRUE(r.normal_unique);
  EXPECT_LE((r.normal - c.normalized()).norm(), 1e-14);
  EXPECT_LE((r.point_a - (Vec(1, 2, 3) + 0.5 * c.normalized())).norm(), 1e-14);

  r = exact_signed_distance(a, at(Vec::Zero()), b, at(0.5 * c));
  expect_consistent(r, 1);
  EXPECT_NEAR(r.distance, 0.5 * c.norm() - 0.8, 1e-14);
  EXPECT_LE((r.normal - c.normalized()).norm(), 1e-14);

  // Concentric: depth r_a + r_b, every normal attains it.
  r = exact_signed_distance(a, at(Vec::Zero()), b, at(Vec::Zero()));
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.distance, -0.8, 1e-15);
  EXPECT_FALSE(r.normal_unique);
}

TEST(ExactReference, CapsulesParallelAndCrossed) {
  const Shape a = Capsule{0.1, 0.6, 0.0}, b = Capsule{0.15, 0.3, 0.0};
  // Parallel axes 0.7 apart, shifted along the axis: a segment difference.
  ExactResult r = exact_signed_distance(a, at(Vec::Zero()), b, at(Vec(0.7, 0, 0.4)));
  expect_consistent(r, 1);
  EXPECT_EQ(r.dimension, 1);
  EXPECT_NEAR(r.distance, 0.7 - 0.25, 1e-14);
  EXPECT_LE((r.normal - Vec::UnitX()).norm(), 1e-14);
  // Crossed at right angles, 0.2 apart along y: a flat difference, overlapping radii.
  r = exact_signed_distance(a, at(Vec::Zero()), b, turned(kPi / 2, Vec::UnitY(), Vec(0.05, 0.2, 0.1)));
  expect_consistent(r, 1);
  EXPECT_EQ(r.dimension, 2);
  EXPECT_NEAR(r.distance, 0.2 - 0.25, 1e-14);
  EXPECT_TRUE(r.normal_unique);
  EXPECT_LE((r.normal - Vec::UnitY()).norm(), 1e-12);
  // End to end along the axis: 0.1 between the end points.
  r = exact_signed_distance(a, at(Vec::Zero()), b, at(Vec(0, 0, 0.6 + 0.3 + 0.1)));
  expect_consistent(r, 1);
  EXPECT_NEAR(r.distance, 0.1 - 0.25, 1e-14);
  EXPECT_LE((r.normal - Vec::UnitZ()).norm(), 1e-12);
}

TEST(ExactReference, AxisAlignedBoxes) {
  const Shape a = Box{Vec(1.0, 0.5, 0.25), 0.0}, b = Box{Vec(0.2, 0.3, 0.4), 0.0};
  // Separated along x by 0.15, overlapping in y and z: a face gap.
  ExactResult r = exact_signed_distance(a, at(Vec(10, 20, 30)), b, at(Vec(10 + 1.35, 20.1, 30.05)));
  expect_consistent(r, 30);
  EXPECT_NEAR(r.distance, 0.15, 1e-13);
  EXPECT_TRUE(r.normal_unique);
  EXPECT_LE((r.normal - Vec::UnitX()).norm(), 1e-13);
  // Separated diagonally: closest corner to corner.
  r = exact_signed_distance(a, at(Vec::Zero()), b, at(Vec(1.2 + 0.3, 0.8 + 0.4, 0)));
  expect_consistent(r, 1);
  EXPECT_NEAR(r.distance, 0.5, 1e-14);  // (0.3, 0.4, 0)
  EXPECT_LE((r.normal - Vec(0.6, 0.8, 0)).norm(), 1e-13);
  // Overlapping: the overlaps are x 0.1, y 0.8 - 0.6 = 0.2... the least is z: 0.05.
  r = exact_signed_distance(a, at(Vec::Zero()), b, at(Vec(1.1, 0.0, 0.6)));
  expect_consistent(r, 1);
  EXPECT_NEAR(r.distance, -0.05, 1e-14);
  EXPECT_TRUE(r.normal_unique);
  EXPECT_LE((r.normal - Vec::UnitZ()).norm(), 1e-13);
  // Coincident centres of equal cubes: depth 2h, three axes tie.
  r = exact_signed_distance(Box{Vec(0.5, 0.5, 0.5), 0.0}, at(Vec::Zero()), Box{Vec(0.5, 0.5, 0.5), 0.0},
                            at(Vec::Zero()));
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.distance, -1.0, 1e-14);
  EXPECT_FALSE(r.normal_unique);
  // Touching faces with a margin: the rounded box reaches 0.05 past the face.
  r = exact_signed_distance(Box{Vec(0.5, 0.5, 0.5), 0.05}, at(Vec::Zero()), b, at(Vec(0.7, 0.1, 0.0)));
  expect_consistent(r, 1);
  EXPECT_NEAR(r.distance, -0.05, 1e-14);
  EXPECT_LE((r.normal - Vec::UnitX()).norm(), 1e-13);
}

TEST(ExactReference, BoxSphere) {
  const Shape box = Box{Vec(0.5, 0.5, 0.5), 0.0};
  const Shape ball = Sphere{0.2, 0.0};
  const Pose box_pose = turned(0.3, Vec(1, 2, 3), Vec(-4, 5, 6));
  // Over a face, 0.1 deep; over a corner, separated.
  const Vec face_normal = box_pose.rotation * Vec::UnitY();
  ExactResult r = exact_signed_distance(box, box_pose, ball, at(box_pose.apply(Vec(0.1, 0.6, -0.2))));
  expect_consistent(r, 10);
  EXPECT_NEAR(r.distance, 0.1 - 0.2, 1e-13);
  EXPECT_LE((r.normal - face_normal).norm(), 1e-12);
  const Vec corner(0.5, -0.5, 0.5), out = Vec(1, -2, 2).normalized();
  r = exact_signed_distance(box, box_pose, ball, at(box_pose.apply(corner + 0.5 * out)));
  expect_consistent(r, 10);
  EXPECT_NEAR(r.distance, 0.5 - 0.2, 1e-13);
  EXPECT_LE((r.normal - box_pose.rotation * out).norm(), 1e-12);
  // Sphere centre inside the box, 0.15 under the +z face.
  r = exact_signed_distance(ball, at(box_pose.apply(Vec(0.1, 0.2, 0.35))), box, box_pose);
  expect_consistent(r, 10);
  EXPECT_NEAR(r.distance, -(0.15 + 0.2), 1e-13);
  EXPECT_LE((r.normal + box_pose.rotation * Vec::UnitZ()).norm(), 1e-12);  // A is the ball
}

TEST(ExactReference, FlatAndSegmentHulls) {
  const Shape square = Polyhedron{make_hull({Vec(-1, -1, 0), Vec(1, -1, 0), Vec(1, 1, 0), Vec(-1, 1, 0)}), 0.0};
  const Shape needle = Polyhedron{make_hull({Vec(0, 0, -1), Vec(0, 0, 1)}), 0.0};
  const Shape ball = Sphere{0.25, 0.0};
  ExactResult r = exact_signed_distance(square, at(Vec::Zero()), ball, at(Vec(0.3, 0.2, 0.5)));
  expect_consistent(r, 1);
  EXPECT_EQ(r.dimension, 2);
  EXPECT_NEAR(r.distance, 0.25, 1e-14);
  EXPECT_LE((r.normal - Vec::UnitZ()).norm(), 1e-14);
  r = exact_signed_distance(square, at(Vec::Zero()), ball, at(Vec(1.3, 1.4, 0.0)));
  expect_consistent(r, 1);
  EXPECT_NEAR(r.distance, 0.5 - 0.25, 1e-14);
  r = exact_signed_distance(needle, at(Vec::Zero()), ball, at(Vec(0.6, 0.8, 3.0)));
  expect_consistent(r, 1);
  EXPECT_EQ(r.dimension, 1);
  EXPECT_NEAR(r.distance, std::sqrt(1.0 + 4.0) - 0.25, 1e-14);
  // A segment hull through the square's interior: the difference is the box
  // [-1.5, 0.5]^2 x [-1, 1]; the needle leaves along +x or +y after 0.5.
  r = exact_signed_distance(square, at(Vec::Zero()), needle, at(Vec(0.5, 0.5, 0.0)));
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_NEAR(r.distance, -0.5, 1e-14);
  EXPECT_FALSE(r.normal_unique);
  // Two squares in one plane, apart: a flat difference.
  r = exact_signed_distance(square, at(Vec::Zero()), square, turned(0.3, Vec::UnitZ(), Vec(4, 0, 0)));
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_EQ(r.dimension, 2);
  const double reach = std::sqrt(2.0) * std::cos(kPi / 4 - 0.3);  // the turned square's half width along x
  EXPECT_NEAR(r.distance, 4 - 1 - reach, 1e-14);
  EXPECT_LE((r.normal - Vec::UnitX()).norm(), 1e-12);
  // Against a box: solid difference, separated by 0.5 over the face.
  r = exact_signed_distance(Box{Vec(1, 1, 1), 0.0}, at(Vec::Zero()), square, turned(0.2, Vec::UnitZ(), Vec(0, 0, 1.5)));
  expect_consistent(r, 1);
  EXPECT_NEAR(r.distance, 0.5, 1e-14);
}

// Cylinders and cones where the closed form is known: the bracket holds it
// and its width stays below 1e-11 of the size.
TEST(ExactReference, CurvedShapesBracketTheClosedForm) {
  const Shape can = Cylinder{0.3, 0.5, 0.0};
  const Shape tip = Cone{0.4, 0.6, 0.0};
  const Shape slab = Box{Vec(2, 2, 0.5), 0.0};
  const Pose slab_pose = at(Vec(0, 0, -0.5));  // top face z = 0
  struct Case {
    const char* what;
    Shape shape;
    Pose pose;
    double lowest;  // the shape's lowest z
  };
  const double tilt = 0.4;
  // Horizontal axes at an angle no polygon vertex sits on, so the contact
  // falls between the initial polygon's vertices.
  const Vec axis(std::cos(0.1234), std::sin(0.1234), 0.0);
  const Vec axis2(std::cos(1.1), std::sin(1.1), 0.0);
  // A cylinder tilted by `tilt` about x: lowest point h cos + r sin below the centre.
  // A cone apex down (turned by pi): lowest point the apex, h below the centre.
  // A cone tilted by `tilt`: lowest of the apex (-h cos... ) and the base rim.
  const double cone_rim = -(-0.6 * std::cos(tilt) - 0.4 * std::sin(tilt));  // base centre at -h, rim down
  const double cone_apex = 0.6 * std::cos(tilt);
  const Case cases[] = {
      {"cylinder upright, separated", can, at(Vec(0.1, 0.2, 0.5 + 0.07)), 0.07},
      {"cylinder upright, penetrating", can, at(Vec(0.1, 0.2, 0.5 - 0.03)), -0.03},
      {"cylinder tilted, rim separated", can, turned(tilt, axis, Vec(0, 0, 1.0)),
       1.0 - (0.5 * std::cos(tilt) + 0.3 * std::sin(tilt))},
      {"cylinder tilted, rim penetrating", can, turned(tilt, axis2, Vec(0, 0, 0.5)),
       0.5 - (0.5 * std::cos(tilt) + 0.3 * std::sin(tilt))},
      {"cylinder on its side", can, turned(kPi / 2, axis, Vec(0, 0, 0.29)), 0.29 - 0.3},
      {"cone apex down", tip, turned(kPi, Vec::UnitX(), Vec(0, 0, 0.65)), 0.05},
      {"cone tilted, rim down", tip, turned(tilt, axis2, Vec(0, 0, 0.6)), 0.6 - std::max(cone_rim, cone_apex)},
      {"cone on its base, penetrating", tip, at(Vec(0, 0, 0.55)), -0.05},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const ExactResult r = exact_signed_distance(slab, slab_pose, c.shape, c.pose);
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_TRUE(r.curved);
    EXPECT_LE(std::abs(r.distance - c.lowest), r.error_bound);
    EXPECT_LE(r.error_bound, 1e-11);
    std::printf("%-34s error bound %.2e, %d sides, %zu points\n", c.what, r.error_bound, r.polygon_sides,
                r.difference_points);
    EXPECT_LE(r.lower, c.lowest + 1e-15);
    EXPECT_GE(r.upper, c.lowest - 1e-15);
  }
  // Side by side, parallel axes: |d| - r_a - r_b (curved against curved).
  const Shape other = Cylinder{0.2, 0.8, 0.0};
  for (double gap : {0.1, 1e-3, -0.02}) {
    const Vec d = Vec(3, 4, 0).normalized() * (0.5 + gap);
    const ExactResult r = exact_signed_distance(can, at(Vec(7, 7, 7)), other, at(Vec(7, 7, 7.1) + d));
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_LE(std::abs(r.distance - gap), r.error_bound) << gap;
    EXPECT_LE(r.error_bound, 1e-11) << gap;
  }
  // A sphere against a cylinder's rim: the distance to the rim circle.
  const Vec ball_centre(0.5, 0.0, 0.7);  // above and outside the rim at (0.3, 0, 0.5)
  const ExactResult r = exact_signed_distance(can, at(Vec::Zero()), Sphere{0.1, 0.0}, at(ball_centre));
  ASSERT_TRUE(r.ok) << r.reason;
  const double expected = (ball_centre - Vec(0.3, 0, 0.5)).norm() - 0.1;
  EXPECT_LE(std::abs(r.distance - expected), r.error_bound);
  EXPECT_LE(r.error_bound, 1e-11);
  // Near contact against a large box: a cone's apex 1e-6 over a face of
  // half width 3 (the bound would suffer from a normal taken as -v/|v|,
  // whose angle error eps * 3 / 1e-6 costs 3 * angle in the support bound).
  const ExactResult apex =
      exact_signed_distance(Box{Vec(3, 3, 0.5), 0.0}, at(Vec(0, 0, -0.5)), tip,
                            turned(kPi, Vec(std::cos(1.1), std::sin(1.1), 0), Vec(2, 2, 0.6 + 1e-6)));
  ASSERT_TRUE(apex.ok) << apex.reason;
  EXPECT_LE(std::abs(apex.distance - 1e-6), apex.error_bound);
  EXPECT_LE(apex.error_bound, 1e-12);
}

// Needles of aspect ~1e9: qhull's facet planes carry rounding far above its
// precision estimate, so the reference checks its answer against the
// support values along its normal and along -v/|v| and widens its bound
// by the disagreement. The needle of the fuzz finding (world vertices; the
// exact distance from rational arithmetic, see distance_test.cpp) came out
// 1.8714e-6 +- 3e-11 for 1.6575e-6; then random needles with a point a
// hair above a face (distance known by construction).
TEST(ExactReference, NeedlesAreBracketedHonestly) {
  const std::vector<Vec> needle = {{0x1.0f7c00000225cp+9, -0x1.d2235f10edca3p-20, 0x1.d26817408e65ap-20},
                                   {-0x1.b25ffffffeed4p+10, 0x1.12e0be826d695p-30, 0.0},
                                   {0x1.12e0be826d695p-30, 0x1.12e0be826d695p-30, 0x1.d26817408e65ap-20},
                                   {-0x1.d2235ed05f64ap-20, -0x1.d2235f10edca3p-20, 0x1.d26817408e65ap-20}};
  const std::vector<Vec> segment = {{0x1.12e0be826d695p-30, 0x1.12e0be826d695p-30, 0x1.12e0be826d695p-30},
                                    {0x1.5d878f94d4ac4p-14, 0x1.17a315aca55e7p-16, -0x1.179a7ea6b14bcp-16}};
  const double exact = 1.6574544818578296e-06;
  for (const bool swapped : {false, true}) {
    const ExactResult r = swapped ? exact_signed_distance(segment, needle) : exact_signed_distance(needle, segment);
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_NEAR(r.distance, exact, r.error_bound) << swapped;
  }
  std::mt19937_64 rng(23);
  int wide = 0;
  for (int i = 0; i < 1000; ++i) {
    const testing::NeedleAndPoint c = testing::needle_and_point_above_it(rng);
    const ExactResult r = exact_signed_distance(c.needle, {c.point});
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_NEAR(r.distance, c.gap, r.error_bound + c.slack) << i;
    wide += r.error_bound > 1e-9 * c.length ? 1 : 0;
  }
  std::printf("%d of 1000 needle brackets wider than 1e-9 of the length\n", wide);
}

// Nearly coaxial cylinders and a cone in a cylinder (axes 1e-10 .. 1e-3 rad
// apart, deep: the bench's deep family). Inscribed polygons alone left
// brackets up to 1.5e-2 wide there (the depth is almost the same over a
// circle of directions); the meridian bracket of the parallel pair made them
// 2 theta R wide; the cutting planes on the difference's support points make
// them 1e-11 of the size wide once the centres are apart. Coincident centres
// are the hardest case: a whole ring of depths within theta R of each
// other, which inscribed hulls resolve only with ~1/sqrt(theta) points (at
// theta = 4e-6 the 8 000-point budget leaves 2.6e-6 of the size; the
// meridian's 2 theta R is the tighter below 1e-6). The
// brackets must hold the best lower bound found over the kink circles
// (support values from closed forms) and hedra's answer (its certified
// branch and bound, a different method).
TEST(ExactReference, NearlyCoaxialCurvedPairsAreBracketedTightly) {
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  const std::array<double, 6> offsets = {0.0, 1e-4, 1e-3, 1e-2, 0.1, 0.3};
  const Cylinder inner{0.4, 0.6, 0.0};
  const double size = bounding_radius(inner);
  double widest_apart = 0.0, widest_coincident = 0.0;
  for (int i = 0; i < 48; ++i) {
    const Shape a = i % 2 ? Shape(Cone{0.5, 0.7, 0.0}) : Shape(Cylinder{0.5, 0.7, 0.0});
    const double tilt = std::pow(10.0, -10.0 + 7.0 * u(rng));
    const Eigen::Matrix3d ra = Eigen::Quaterniond{g(rng), g(rng), g(rng), g(rng)}.normalized().toRotationMatrix();
    const Eigen::Matrix3d rb = ra * Eigen::AngleAxisd(tilt, random_unit(rng)).toRotationMatrix();
    const double offset = offsets[(i / 2) % offsets.size()];
    const Pose pa{ra, Vec::Zero()}, pb{rb, offset * 0.7 * random_unit(rng)};
    const ExactResult r = exact_signed_distance(a, pa, inner, pb);
    ASSERT_TRUE(r.ok) << r.reason;
    const double lower = testing::lower_bound_over_great_circles(a, pa, inner, pb, {Vec(ra.col(2)), Vec(rb.col(2))});
    EXPECT_GE(r.upper, lower - 1e-12) << i;
    const double width = r.upper - r.lower;
    EXPECT_LE(width, 4.0 * tilt * size + 1e-12) << i << " tilt " << tilt;
    EXPECT_LE(width, (offset > 0.0 ? 1e-11 : 4e-6) * size) << i << " tilt " << tilt << " offset " << offset;
    double& widest = offset > 0.0 ? widest_apart : widest_coincident;
    widest = std::max(widest, width);
    const PenetrationResult h = penetration(a, pa, Shape(inner), pb);
    ASSERT_EQ(h.status, Status::ok) << i;
    EXPECT_GE(h.distance, r.lower - h.error_bound - 1e-12 * size) << i;
    EXPECT_LE(h.distance, r.upper + h.error_bound + 1e-12 * size) << i;
  }
  std::printf("widest bracket / size: centres apart %.2e, coincident %.2e\n", widest_apart / size,
              widest_coincident / size);
}

// Coincident cylinders whose half lengths exceed their radii, at any tilt:
// every direction has support value r_a sin + h_a |cos| >= r_a on A (and
// likewise on B), with equality perpendicular to both axes, so the depth is
// exactly r_a + r_b. The meridian section alone brackets it to 2 theta R.
TEST(ExactReference, TiltedCoincidentCylindersHaveTheSumOfTheirRadiiAsDepth) {
  std::mt19937_64 rng(33);
  std::normal_distribution<double> g(0.0, 1.0);
  const Cylinder a{0.5, 0.7, 0.0}, b{0.4, 0.6, 0.0};
  for (const double tilt : {1e-5, 1e-4, 1e-3, 1e-2, 0.1}) {
    const Eigen::Matrix3d ra = Eigen::Quaterniond{g(rng), g(rng), g(rng), g(rng)}.normalized().toRotationMatrix();
    const Eigen::Matrix3d rb = ra * Eigen::AngleAxisd(tilt, random_unit(rng)).toRotationMatrix();
    const Vec centre = random_unit(rng);
    const ExactResult r = exact_signed_distance(a, Pose{ra, centre}, b, Pose{rb, centre});
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_LE(r.lower, -0.9 + 1e-14) << tilt;
    EXPECT_GE(r.upper, -0.9 - 1e-14) << tilt;
    EXPECT_LE(r.upper - r.lower, 1e-9) << tilt;
  }
}

TEST(ExactReference, BadInputIsRefusedWithAReason) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  ExactResult r = exact_signed_distance(Sphere{1.0, 0.0}, at(Vec(nan, 0, 0)), Sphere{1.0, 0.0}, at(Vec::Zero()));
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("pose"), std::string::npos) << r.reason;
  r = exact_signed_distance(Sphere{-1.0, 0.0}, at(Vec::Zero()), Sphere{1.0, 0.0}, at(Vec::Zero()));
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("shape a"), std::string::npos) << r.reason;
  r = exact_signed_distance(std::vector<Vec>{Vec(0, 0, nan)}, std::vector<Vec>{Vec::Zero()});
  EXPECT_FALSE(r.ok);
}

// Seeded random hull pairs (some separated, some overlapping): hedra's
// distance and penetration agree with the reference, and the reference's
// point-set entry equals its shape entry.
TEST(ExactReference, AgreesWithHedraOnRandomPolytopes) {
  std::mt19937_64 rng(77);
  int separated = 0, overlapping = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const std::vector<Vec> pa = random_points(rng, 12, Vec(1.0, 0.6, 0.4));
    const std::vector<Vec> pb = random_points(rng, 10, Vec(0.5, 0.7, 0.3));
    const Shape a = Polyhedron{make_hull(pa), 0.0}, b = Polyhedron{make_hull(pb), 0.0};
    const Pose pose_a =
        Pose::from_quaternion(Eigen::Quaterniond(Eigen::AngleAxisd(0.7 * trial, random_unit(rng))), Vec::Zero());
    const Pose pose_b = Pose::from_quaternion(Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * trial, random_unit(rng))),
                                              (0.3 + 0.04 * trial) * random_unit(rng));
    reference::ExactSettings settings;
    settings.override_a = &pa;
    settings.override_b = &pb;
    const ExactResult r = exact_signed_distance(a, pose_a, b, pose_b, settings);
    ASSERT_TRUE(r.ok) << r.reason;
    const ExactResult w = exact_signed_distance(testing::posed(pa, pose_a), testing::posed(pb, pose_b));
    ASSERT_TRUE(w.ok) << w.reason;
    EXPECT_NEAR(r.distance, w.distance, 1e-12);
    (r.distance > 0 ? separated : overlapping)++;
    const PenetrationResult p = penetration(a, pose_a, b, pose_b);
    ASSERT_EQ(p.status, Status::ok);
    EXPECT_NEAR(p.distance, r.distance, 1e-9) << trial;
    if (r.normal_unique) {
      EXPECT_LE((p.normal - r.normal).norm(), 1e-6) << trial;
    }
    const DistanceResult d = distance(a, pose_a, b, pose_b);
    ASSERT_EQ(d.status, Status::ok);
    EXPECT_NEAR(d.distance, std::max(0.0, r.distance), 1e-9) << trial;
  }
  EXPECT_GT(separated, 5);
  EXPECT_GT(overlapping, 5);
}

}  // namespace
}  // namespace hedra::collision
