// GJK distance and intersection through the embedding API, checked against
// answers computed without GJK:
//   * closed forms: sphere-sphere, capsule-capsule (segment-segment distance
//     as the minimum of a convex quadratic over the unit square), axis-aligned
//     box-box (per-axis gaps), sphere-box (clamp into the box);
//   * the exact reference: the distance from the origin to the convex hull of
//     the Minkowski difference {a_i - b_j}, built by qhull, as the minimum
//     point-triangle distance over its facets (0 when the origin is inside);
//   * properties: swapping A and B, moving both rigidly, witness points on
//     the supporting planes (the optimality condition of the distance),
//     intersect() agreeing with distance();
//   * the hard cases of field-notes.md that apply to distance: offsets of
//     1e6, scale disparity 1e-3 vs 1e3, thin plates and needles, exact
//     touching, duplicate support points, flat and segment hulls;
//   * no heap allocation per query (a counting global operator new).
// Agreement is required within 1e-9 of the shapes' size. Fixed seeds.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <hedra/collision/detail/gjk.hpp>
#include <hedra/collision/manifold.hpp>
#include <hedra/collision/query.hpp>
#include <limits>
#include <new>
#include <qhull_reference.hpp>
#include <random>
#include <vector>

#include "allocation_counter.hpp"
#include "collision_test_support.hpp"

namespace hedra::collision {
namespace {

using namespace hedra::collision::testing;

using Vec = Eigen::Vector3d;

Pose random_pose(std::mt19937_64& rng, double spread) {
  std::uniform_real_distribution<double> u(-spread, spread);
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  return Pose::from_quaternion(q, Vec(u(rng), u(rng), u(rng)));
}

// ---- independent references ------------------------------------------------

// The optimality conditions of a distance answer: unit normal, witness
// points on the supporting planes of both shapes orthogonal to the normal,
// and point_b - point_a = distance * normal.
void expect_optimal(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb, const DistanceResult& r,
                    double tol) {
  ASSERT_EQ(r.status, Status::ok);
  ASSERT_FALSE(r.intersecting);
  EXPECT_NEAR(r.normal.norm(), 1.0, 1e-12);
  EXPECT_NEAR(r.normal.dot(r.point_a), support_value(a, pa, r.normal), tol);
  EXPECT_NEAR(-r.normal.dot(r.point_b), support_value(b, pb, -r.normal), tol);
  EXPECT_LT((r.point_b - r.point_a - r.distance * r.normal).norm(), tol);
}

// ---- closed forms -------------------------------------------------------------

TEST(GjkDistance, SphereSphereClosedForm) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> radius(0.01, 2.0);
  int separated = 0;
  for (int i = 0; i < 2000; ++i) {
    const Sphere a{radius(rng), i % 3 == 0 ? 0.1 : 0.0}, b{radius(rng), 0.0};
    const Pose pa = random_pose(rng, 3.0), pb = random_pose(rng, 3.0);
    const Vec delta = pb.translation - pa.translation;
    const double expected = delta.norm() - core_radius(a) - core_radius(b);
    const DistanceResult r = distance(a, pa, b, pb);
    ASSERT_EQ(r.status, Status::ok);
    const double size = std::max(core_radius(a), core_radius(b));
    if (expected > 1e-9 * size) {
      ++separated;
      ASSERT_FALSE(r.intersecting);
      EXPECT_NEAR(r.distance, expected, 1e-9 * size);
      EXPECT_LT((r.normal - delta.normalized()).norm(), 1e-12);
      EXPECT_LT((r.point_a - (pa.translation + core_radius(a) * delta.normalized())).norm(), 1e-9 * size);
      EXPECT_EQ(r.iterations, 1);  // two points: the first support is the answer
    } else if (expected < -1e-9 * size) {
      EXPECT_TRUE(r.intersecting);
      EXPECT_EQ(r.distance, 0.0);
    }
  }
  EXPECT_GT(separated, 200);
  EXPECT_LT(separated, 1900);
}

TEST(GjkDistance, CapsuleCapsuleClosedForm) {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> len(0.0, 2.0), rad(0.01, 0.5);
  int separated = 0;
  for (int i = 0; i < 2000; ++i) {
    const double la = len(rng), ra = rad(rng), lb = len(rng), rb = rad(rng);  // the seeded draw order
    const Capsule a{ra, la, 0.0}, b{rb, lb, i % 4 == 0 ? 0.05 : 0.0};
    Pose pa = random_pose(rng, 1.5), pb = random_pose(rng, 1.5);
    if (i % 10 == 0) pb.rotation = pa.rotation;  // parallel segments
    const Vec za = pa.rotation.col(2), zb = pb.rotation.col(2);
    const double core = segment_distance(pa.translation - a.half_length * za, pa.translation + a.half_length * za,
                                         pb.translation - b.half_length * zb, pb.translation + b.half_length * zb);
    const double expected = core - core_radius(a) - core_radius(b);
    const double size = std::max(bounding_radius(a), bounding_radius(b));
    const DistanceResult r = distance(a, pa, b, pb);
    ASSERT_EQ(r.status, Status::ok);
    if (expected > 1e-9 * size) {
      ++separated;
      ASSERT_FALSE(r.intersecting) << i;
      EXPECT_NEAR(r.distance, expected, 1e-9 * size) << i;
      expect_optimal(a, pa, b, pb, r, 1e-9 * size);
    } else if (expected < -1e-9 * size) {
      EXPECT_TRUE(r.intersecting) << i;
    }
  }
  EXPECT_GT(separated, 200);
  EXPECT_LT(separated, 1900);
}

double box_box_distance(const Vec& ca, const Vec& ha, const Vec& cb, const Vec& hb) {
  return ((cb - ca).cwiseAbs() - ha - hb).cwiseMax(0.0).norm();
}

TEST(GjkDistance, AxisAlignedBoxBoxClosedForm) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ext(0.05, 1.5);
  int separated = 0;
  for (int i = 0; i < 2000; ++i) {
    const Box a{{ext(rng), ext(rng), ext(rng)}, 0.0}, b{{ext(rng), ext(rng), ext(rng)}, 0.0};
    // A common rotation: the boxes stay aligned with each other.
    Pose pa = random_pose(rng, 3.0), pb = random_pose(rng, 3.0);
    pb.rotation = pa.rotation;
    const Vec local = pa.rotation.transpose() * (pb.translation - pa.translation);
    const double expected = box_box_distance(Vec::Zero(), a.half_extents, local, b.half_extents);
    const double size = std::max(bounding_radius(a), bounding_radius(b));
    const DistanceResult r = distance(a, pa, b, pb);
    ASSERT_EQ(r.status, Status::ok);
    if (expected > 1e-9 * size) {
      ++separated;
      ASSERT_FALSE(r.intersecting);
      EXPECT_NEAR(r.distance, expected, 1e-9 * size);
      expect_optimal(a, pa, b, pb, r, 1e-9 * size);
      EXPECT_GE(r.error_bound, 0.0);
    } else {
      EXPECT_TRUE(r.intersecting || r.distance <= 1e-9 * size);
    }
  }
  EXPECT_GT(separated, 200);
  EXPECT_LT(separated, 1900);
}

TEST(GjkDistance, SphereBoxClosedForm) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> ext(0.05, 1.5);
  int separated = 0;
  for (int i = 0; i < 2000; ++i) {
    const Box box{{ext(rng), ext(rng), ext(rng)}, i % 5 == 0 ? 0.1 : 0.0};
    const Sphere ball{ext(rng), 0.0};
    const Pose pb = random_pose(rng, 3.0), ps = random_pose(rng, 3.0);
    const Vec c = pb.rotation.transpose() * (ps.translation - pb.translation);
    const Vec clamped = c.cwiseMax(-box.half_extents).cwiseMin(box.half_extents);
    const double expected = (c - clamped).norm() - ball.radius - box.margin;
    const double size = std::max(bounding_radius(box), ball.radius);
    const DistanceResult r = distance(box, pb, ball, ps);
    ASSERT_EQ(r.status, Status::ok);
    if (expected > 1e-9 * size) {
      ++separated;
      ASSERT_FALSE(r.intersecting);
      EXPECT_NEAR(r.distance, expected, 1e-9 * size);
      expect_optimal(box, pb, ball, ps, r, 1e-9 * size);
    } else if (expected < -1e-9 * size) {
      EXPECT_TRUE(r.intersecting);
    }
  }
  EXPECT_GT(separated, 200);
  EXPECT_LT(separated, 1900);
}

// ---- the exact reference: qhull on the Minkowski difference --------------

TEST(GjkDistance, RandomPolytopePairsMatchMinkowskiHullReference) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> count(4, 64);
  std::uniform_real_distribution<double> ext(0.2, 2.0);
  int separated = 0, overlapping = 0;
  double worst = 0.0;
  for (int i = 0; i < 400; ++i) {
    const auto ha = make_hull(random_points(rng, count(rng), {ext(rng), ext(rng), ext(rng)}));
    const auto hb = make_hull(random_points(rng, count(rng), {ext(rng), ext(rng), ext(rng)}));
    const Polyhedron a{ha, 0.0}, b{hb, 0.0};
    const Pose pa = random_pose(rng, 2.5), pb = random_pose(rng, 2.5);
    const double expected = reference_distance(world_vertices(*ha, pa), world_vertices(*hb, pb));
    const double size = std::max(ha->bounding_radius(), hb->bounding_radius());
    const DistanceResult r = distance(a, pa, b, pb);
    ASSERT_EQ(r.status, Status::ok);
    if (expected > 1e-9 * size) {
      ++separated;
      ASSERT_FALSE(r.intersecting) << i;
      EXPECT_NEAR(r.distance, expected, 1e-9 * size) << i;
      // The certified bound holds: true distance >= distance - error_bound.
      EXPECT_GE(expected, r.distance - r.error_bound - 1e-12 * size);
      worst = std::max(worst, std::abs(r.distance - expected) / size);
      expect_optimal(a, pa, b, pb, r, 1e-9 * size);
    } else if (expected == 0.0) {
      ++overlapping;
      EXPECT_TRUE(r.intersecting || r.distance <= 1e-9 * size) << i;
    }
  }
  EXPECT_GT(separated, 50);
  EXPECT_GT(overlapping, 50);
  RecordProperty("worst_relative_error", std::to_string(worst));
}

// ---- properties -------------------------------------------------------------

std::vector<Shape> shape_zoo(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> ext(0.1, 1.0);
  return {Sphere{ext(rng), 0.0},
          Box{{ext(rng), ext(rng), ext(rng)}, 0.0},
          Box{{ext(rng), ext(rng), ext(rng)}, 0.05},
          [&] {  // half length drawn first, as before the field order changed
            const double half_length = ext(rng);
            return Capsule{ext(rng), half_length, 0.0};
          }(),
          Cylinder{ext(rng), ext(rng), 0.0},
          Cone{ext(rng), ext(rng), 0.0},
          Polyhedron{make_hull(random_points(rng, 30, {ext(rng), ext(rng), ext(rng)})), 0.0},
          Polyhedron{make_hull(random_points(rng, 200, {1.0, 0.5, 0.7})), 0.02}};
}

TEST(GjkDistance, SwapRigidMotionAndIntersectAgree) {
  std::mt19937_64 rng(6);
  const std::vector<Shape> zoo = shape_zoo(rng);
  int separated = 0, overlapping = 0;
  for (int i = 0; i < 3000; ++i) {
    const Shape& a = zoo[i % zoo.size()];
    const Shape& b = zoo[(i / zoo.size()) % zoo.size()];
    const Pose pa = random_pose(rng, 1.5), pb = random_pose(rng, 1.5);
    const double size = std::max(bounding_radius(a), bounding_radius(b));
    const DistanceResult r = distance(a, pa, b, pb);
    ASSERT_EQ(r.status, Status::ok) << i;
    ASSERT_TRUE(std::isfinite(r.distance) && r.normal.allFinite() && r.point_a.allFinite());
    const IntersectResult hit = intersect(a, pa, b, pb);
    ASSERT_EQ(hit.status, Status::ok);
    // Curved shapes converge to the tolerance only: leave a band for them.
    if (r.distance > 1e-6 * size || r.intersecting) {
      EXPECT_EQ(hit.intersecting, r.intersecting) << i;
    }
    if (r.intersecting) {
      ++overlapping;
      continue;
    }
    ++separated;
    expect_optimal(a, pa, b, pb, r, 1e-6 * size);
    // Cylinders and cones are curved: GJK converges on them to the distance
    // tolerance (1e-10 relative), and the normal's angle then only to about
    // its square root. Polytope cores (points, segments, boxes, hulls)
    // terminate exactly, so their unique normals must agree to 1e-6.
    const auto curved = [](const Shape& s) {
      return std::holds_alternative<Cylinder>(s) || std::holds_alternative<Cone>(s);
    };
    const double normal_tolerance = curved(a) || curved(b) ? 1e-4 : 1e-6;
    const DistanceResult swapped = distance(b, pb, a, pa);
    EXPECT_NEAR(swapped.distance, r.distance, 1e-9 * size);
    EXPECT_LT((swapped.normal + r.normal).norm(), normal_tolerance) << a.index() << " " << b.index();
    const Pose motion = random_pose(rng, 10.0);
    const Pose ma{motion.rotation * pa.rotation, motion.apply(pa.translation)};
    const Pose mb{motion.rotation * pb.rotation, motion.apply(pb.translation)};
    const DistanceResult moved = distance(a, ma, b, mb);
    EXPECT_NEAR(moved.distance, r.distance, 1e-9 * size);
    EXPECT_LT((moved.normal - motion.rotation * r.normal).norm(), normal_tolerance);
    // Moving B by -distance * normal brings the pair to touching.
    const Pose touching{pb.rotation, pb.translation - r.distance * r.normal};
    EXPECT_LT(distance(a, pa, b, touching).distance, 1e-6 * size);
  }
  EXPECT_GT(separated, 500);
  EXPECT_GT(overlapping, 500);
}

TEST(GjkDistance, WarmStartFromCacheGivesTheSameAnswer) {
  std::mt19937_64 rng(7);
  const auto big = make_hull(random_points(rng, 5000, {1.0, 1.0, 1.0}));
  const Polyhedron a{big, 0.0}, b{big, 0.0};
  GjkCache cache;
  Pose pa = Pose::identity();
  int cold_iterations = 0, warm_iterations = 0;
  for (int step = 0; step < 200; ++step) {
    const double angle = 0.01 * step;
    const Pose pb = Pose::from_quaternion(Eigen::Quaterniond(Eigen::AngleAxisd(angle, Vec::UnitZ())),
                                          Vec(3.0 + std::cos(angle), std::sin(angle), 0.2));
    const DistanceResult cold = distance(a, pa, b, pb);
    const DistanceResult warm = distance(a, pa, b, pb, &cache);
    ASSERT_EQ(warm.status, Status::ok);
    EXPECT_NEAR(warm.distance, cold.distance, 1e-9);
    cold_iterations += cold.iterations;
    warm_iterations += warm.iterations;
  }
  EXPECT_TRUE(cache.valid);
  EXPECT_LT(warm_iterations, cold_iterations);
}

// ---- hard cases ------------------------------------------------------------

TEST(GjkHardCases, OffsetsOfOneMillion) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> ext(0.05, 1.5);
  for (int i = 0; i < 500; ++i) {
    const Box a{{ext(rng), ext(rng), ext(rng)}, 0.0}, b{{ext(rng), ext(rng), ext(rng)}, 0.0};
    Pose pa = random_pose(rng, 3.0), pb = random_pose(rng, 3.0);
    pb.rotation = pa.rotation;
    const Vec local = pa.rotation.transpose() * (pb.translation - pa.translation);
    const double expected = box_box_distance(Vec::Zero(), a.half_extents, local, b.half_extents);
    const Vec far = Vec(1e6, -1e6, 1e6) * (i % 2 ? 1.0 : -1.0);
    // The offset is added after the relative placement, so that the pair
    // itself is exactly the same: only the world coordinates grow.
    const Pose fa{pa.rotation, far}, fb{pb.rotation, far + (pb.translation - pa.translation)};
    const double moved = box_box_distance(Vec::Zero(), a.half_extents,
                                          pa.rotation.transpose() * (fb.translation - fa.translation), b.half_extents);
    const DistanceResult r = distance(a, fa, b, fb);
    ASSERT_EQ(r.status, Status::ok);
    const double size = std::max(bounding_radius(a), bounding_radius(b));
    if (moved > 1e-9 * size) {
      EXPECT_NEAR(r.distance, moved, 1e-9 * size) << i;
      EXPECT_NEAR(moved, expected, 1e-9);  // the subtraction of 1e6 offsets was exact enough
    }
  }
  // Polyhedra built from points far away are recentred: same answer as near.
  const std::vector<Vec> near_points = random_points(rng, 40, {1.0, 0.5, 0.3});
  std::vector<Vec> far_points;
  for (const Vec& v : near_points) far_points.push_back(v + Vec(1e6, 2e6, -3e6));
  const auto near_hull = make_hull(near_points), far_hull = make_hull(far_points);
  const DistanceResult near_r =
      distance(Polyhedron{near_hull, 0.0}, Pose::identity(), Sphere{0.1, 0.0}, Pose::from_translation({2, 1, 0}));
  const DistanceResult far_r = distance(Polyhedron{far_hull, 0.0}, Pose::from_translation(Vec(-1e6, -2e6, 3e6)),
                                        Sphere{0.1, 0.0}, Pose::from_translation({2, 1, 0}));
  EXPECT_NEAR(far_r.distance, near_r.distance, 1e-9);
}

TEST(GjkHardCases, ScaleDisparityAndThinShapes) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  struct Pair {
    Vec ha, hb;
  };
  const std::vector<Pair> pairs = {
      {{1e-3, 1e-3, 1e-3}, {1e3, 1e3, 1e3}},  // a grain next to a building
      {{1e3, 1e3, 1e-1}, {1e-3, 1e-3, 1e-3}},
      {{1.0, 1.0, 1e-4}, {1.0, 1.0, 1e-4}},    // thin plates (aspect 1e4)
      {{1e-4, 1e-4, 1.0}, {1e-4, 1e-4, 1.0}},  // needles
  };
  for (const Pair& p : pairs) {
    const Box a{p.ha, 0.0}, b{p.hb, 0.0};
    const double size = std::max(p.ha.norm(), p.hb.norm());
    const double small = std::min(p.ha.minCoeff(), p.hb.minCoeff());
    int separated = 0;
    for (int i = 0; i < 400; ++i) {
      // Gaps of the order of the smaller shape, in a common rotated frame.
      const Eigen::Matrix3d rot = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
      // B just beyond one face of A (gap up to 5x the smaller size), anywhere
      // along the other two axes: face, edge and corner regions.
      Vec local = 1.2 * (p.ha + p.hb).cwiseProduct(Vec(u(rng), u(rng), u(rng)));
      const int k = i % 3;
      local[k] = (u(rng) < 0 ? -1.0 : 1.0) * (p.ha[k] + p.hb[k] + 2.5 * small * (1.0 + u(rng)));
      const Pose pa{rot, Vec(u(rng), u(rng), u(rng))};
      const Pose pb{rot, pa.translation + rot * local};
      const double expected = box_box_distance(Vec::Zero(), p.ha, local, p.hb);
      const DistanceResult r = distance(a, pa, b, pb);
      ASSERT_EQ(r.status, Status::ok);
      if (expected > 1e-9 * size) {
        ++separated;
        EXPECT_NEAR(r.distance, expected, 1e-9 * size) << p.ha.transpose() << " / " << p.hb.transpose();
        EXPECT_NEAR(r.normal.norm(), 1.0, 1e-12);
      }
    }
    EXPECT_GT(separated, 20);
  }
  // A 1e-3 sphere near a 1e3 box face: distance and normal exact.
  const DistanceResult r = distance(Box{{1e3, 1e3, 1e3}, 0.0}, Pose::identity(), Sphere{1e-3, 0.0},
                                    Pose::from_translation({10.0, -20.0, 1e3 + 3e-3}));
  EXPECT_NEAR(r.distance, 2e-3, 1e-9 * 1e-3 * 1e3);
  EXPECT_LT((r.normal - Vec::UnitZ()).norm(), 1e-9);  // rounding of 1e3 coordinates / 3e-3
}

// intersect() tests the start axis (the centre difference, or the cache's
// axis) before its loop: a pair that axis separates beyond the margin stops
// after one support call; within the margin it must not.
TEST(GjkIntersect, StopsOnASeparatingStartAxisOnly) {
  const Box unit{{0.5, 0.5, 0.5}, 0.0};
  const IntersectResult apart = intersect(unit, Pose::identity(), unit, Pose::from_translation({3.0, 0.2, 0.0}));
  EXPECT_EQ(apart.status, Status::ok);
  EXPECT_FALSE(apart.intersecting);
  EXPECT_EQ(apart.iterations, 0);
  EXPECT_EQ(apart.support_calls, 1);
  // Spheres: point cores with the radii as margin (2), the centres 2.5 and
  // 1.5 apart: the start axis separates the first pair only.
  const Sphere one{1.0, 0.0};
  const IntersectResult far = intersect(one, Pose::identity(), one, Pose::from_translation({2.5, 0.0, 0.0}));
  EXPECT_FALSE(far.intersecting);
  EXPECT_EQ(far.iterations, 0);
  const IntersectResult near = intersect(one, Pose::identity(), one, Pose::from_translation({1.5, 0.0, 0.0}));
  EXPECT_EQ(near.status, Status::ok);
  EXPECT_TRUE(near.intersecting);
  // The centre difference does not separate two long bars crossed beside
  // each other (it points across both): the loop decides, and agrees with
  // distance().
  const Box bar{{2.0, 0.1, 0.1}, 0.0};
  const Pose turned{Eigen::AngleAxisd(0.5 * M_PI, Vec::UnitZ()).toRotationMatrix(), Vec(1.5, 1.5, 0.0)};
  const IntersectResult crossed = intersect(bar, Pose::identity(), bar, turned);
  const DistanceResult d = distance(bar, Pose::identity(), bar, turned);
  EXPECT_EQ(crossed.intersecting, d.intersecting);
  // A cache holding a separating axis: the next query stops on it.
  GjkCache cache;
  const Pose moved = Pose::from_translation({0.0, 0.0, 1.2});
  const IntersectResult first = intersect(unit, Pose::identity(), unit, moved, &cache);
  EXPECT_FALSE(first.intersecting);
  const IntersectResult again = intersect(unit, Pose::identity(), unit, moved, &cache);
  EXPECT_FALSE(again.intersecting);
  EXPECT_EQ(again.iterations, 0);
}

TEST(GjkHardCases, ExactTouchingFaceEdgeVertex) {
  const Box unit{{0.5, 0.5, 0.5}, 0.0};
  // Face, edge and vertex contact of two axis-aligned unit cubes.
  for (const Vec& t : {Vec(1.0, 0.0, 0.0), Vec(1.0, 1.0, 0.0), Vec(1.0, 1.0, 1.0), Vec(1.0, 0.3, -0.2)}) {
    const DistanceResult r = distance(unit, Pose::identity(), unit, Pose::from_translation(t));
    ASSERT_EQ(r.status, Status::ok) << t.transpose();
    EXPECT_LE(r.distance, 1e-12) << t.transpose();
    EXPECT_TRUE(std::isfinite(r.distance) && r.normal.allFinite());
    const IntersectResult hit = intersect(unit, Pose::identity(), unit, Pose::from_translation(t));
    EXPECT_EQ(hit.status, Status::ok);
  }
  // Touching spheres and capsules: exactly zero.
  const DistanceResult s =
      distance(Sphere{1.0, 0.0}, Pose::identity(), Sphere{2.0, 0.0}, Pose::from_translation({3, 0, 0}));
  EXPECT_TRUE(s.intersecting);
  EXPECT_EQ(s.distance, 0.0);
  // Rotated cube touching a face at a vertex (tilted 45 degrees about two axes).
  const Pose tilted =
      Pose::from_quaternion(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 4, Vec::UnitZ())) *
                                Eigen::Quaterniond(Eigen::AngleAxisd(std::atan(M_SQRT1_2), Vec::UnitX())),
                            Vec::Zero());
  const double reach = support_value(unit, tilted, Vec::UnitZ());
  const DistanceResult v = distance(unit, tilted, unit, Pose::from_translation({0.0, 0.0, reach + 0.5}));
  EXPECT_LE(v.distance, 1e-12);
}

TEST(GjkHardCases, DuplicateSupportPointsAndDegenerateHulls) {
  std::mt19937_64 rng(10);
  // Every input point given three times: same hull, same distance, few iterations.
  std::vector<Vec> points = random_points(rng, 20, {1.0, 1.0, 1.0});
  std::vector<Vec> tripled;
  for (int k = 0; k < 3; ++k) tripled.insert(tripled.end(), points.begin(), points.end());
  const auto h = make_hull(tripled);
  const DistanceResult r = distance(Polyhedron{h, 0.0}, Pose::identity(), Box{{0.5, 0.5, 0.5}, 0.0},
                                    Pose::from_translation({4.0, 0.0, 0.0}));
  ASSERT_EQ(r.status, Status::ok);
  EXPECT_LT(r.iterations, 20);
  std::vector<Vec> box_points;
  for (int i = 0; i < 8; ++i) box_points.emplace_back(i & 1 ? 4.5 : 3.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5);
  EXPECT_NEAR(r.distance, reference_distance(world_vertices(*h, Pose::identity()), box_points), 1e-9);

  // Segment hull vs segment hull: the segment-segment closed form.
  for (int i = 0; i < 200; ++i) {
    const Vec p0 = 2.0 * random_unit(rng), p1 = 2.0 * random_unit(rng);
    const Vec q0 = 2.0 * random_unit(rng) + Vec(3, 0, 0), q1 = 2.0 * random_unit(rng) + Vec(3, 0, 0);
    const auto sa = make_hull({p0, p1}), sb = make_hull({q0, q1});
    ASSERT_EQ(sa->dimension(), 1);
    const DistanceResult d = distance(Polyhedron{sa, 0.0}, Pose::identity(), Polyhedron{sb, 0.0}, Pose::identity());
    ASSERT_EQ(d.status, Status::ok);
    const double expected = segment_distance(p0, p1, q0, q1);
    if (expected > 1e-9) {
      EXPECT_NEAR(d.distance, expected, 1e-9 * 4.0) << i;
    } else {
      EXPECT_LE(d.distance, 1e-9 * 4.0);
    }
  }

  // Flat polygons (two back-to-back faces) vs a box: the qhull reference.
  int checked = 0;
  for (int i = 0; i < 100; ++i) {
    const Vec e1 = random_unit(rng), e2 = e1.unitOrthogonal();
    std::vector<Vec> flat;
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 30; ++k) flat.push_back(u(rng) * e1 + u(rng) * e2);
    const auto fh = make_hull(flat);
    ASSERT_EQ(fh->dimension(), 2);
    const Box box{{0.3, 0.4, 0.5}, 0.0};
    const Pose pb = random_pose(rng, 1.5);
    std::vector<Vec> corners;
    for (int k = 0; k < 8; ++k)
      corners.push_back(pb.apply(Vec(k & 1 ? 0.3 : -0.3, k & 2 ? 0.4 : -0.4, k & 4 ? 0.5 : -0.5)));
    const double expected = reference_distance(world_vertices(*fh, Pose::identity()), corners);
    const DistanceResult d = distance(Polyhedron{fh, 0.0}, Pose::identity(), box, pb);
    ASSERT_EQ(d.status, Status::ok);
    if (expected > 1e-9) {
      ++checked;
      EXPECT_NEAR(d.distance, expected, 1e-9 * 1.5) << i;
    }
  }
  EXPECT_GT(checked, 20);
}

// Fuzz finding (a point hull at x = 8.2e-159 against a point): the squares
// of lengths that small underflow (2e-170 apart read as touching; 8.2e-159
// gave a normal of length 1 - 4.7e-9). A pair whose extent is not zero but
// below min_pair_extent is refused by every query; from min_pair_extent up
// the answers are exact.
TEST(GjkHardCases, PairsBelowTheMinimumExtentAreRefusedAboveItExact) {
  const Vec direction = Vec(1, 2, -2).normalized();
  const Sphere point{0.0, 0.0};
  for (const double x : {8.2e-159, 2.0e-170, 0.5e-60, 1.0e-60, 3.0e-60, 1.0e-30}) {
    const bool in_range = x * direction.cwiseAbs().maxCoeff() >= min_pair_extent;
    const auto point_hull = make_hull({x * direction});
    for (const bool swapped : {false, true}) {
      const Shape a = swapped ? Shape(point) : Shape(Polyhedron{point_hull, 0.0});
      const Shape b = swapped ? Shape(Polyhedron{point_hull, 0.0}) : Shape(point);
      EXPECT_EQ(pair_in_range(a, Pose::identity(), b, Pose::identity()), in_range) << x;
      const IntersectResult i = intersect(a, Pose::identity(), b, Pose::identity());
      const DistanceResult d = distance(a, Pose::identity(), b, Pose::identity());
      const PenetrationResult p = penetration(a, Pose::identity(), b, Pose::identity());
      const ContactResult c = contact(a, Pose::identity(), b, Pose::identity());
      if (!in_range) {
        EXPECT_EQ(i.status, Status::invalid_input) << x;
        EXPECT_EQ(d.status, Status::invalid_input) << x;
        EXPECT_EQ(p.status, Status::invalid_input) << x;
        EXPECT_EQ(c.status, Status::invalid_input) << x;
        EXPECT_TRUE(d.normal.allFinite() && p.normal.allFinite() && d.distance == 0.0 && p.distance == 0.0);
        continue;
      }
      ASSERT_EQ(d.status, Status::ok) << x;
      ASSERT_EQ(p.status, Status::ok) << x;
      EXPECT_FALSE(i.intersecting) << x;
      EXPECT_NEAR(d.distance, x, 4e-16 * x) << x;
      EXPECT_NEAR(p.distance, x, 4e-16 * x) << x;
      EXPECT_NEAR(d.normal.norm(), 1.0, 4e-16) << x;
      EXPECT_NEAR(p.normal.norm(), 1.0, 4e-16) << x;
      EXPECT_NEAR(d.normal.dot(swapped ? direction : Vec(-direction)), 1.0, 4e-16) << x;
    }
  }
  // Coincident points: extent zero, in range, touching.
  const Shape origin = Sphere{0.0, 0.0};
  EXPECT_TRUE(pair_in_range(origin, Pose::identity(), origin, Pose::identity()));
  EXPECT_TRUE(intersect(origin, Pose::identity(), origin, Pose::identity()).intersecting);
  // A tiny shape far from another is in range (the extent is the distance).
  const Shape tiny = Sphere{1e-80, 0.0};
  EXPECT_TRUE(pair_in_range(tiny, Pose::identity(), origin, Pose::from_translation({0.0, 2.0, 0.0})));
  EXPECT_NEAR(distance(tiny, Pose::identity(), origin, Pose::from_translation({0.0, 2.0, 0.0})).distance, 2.0, 1e-15);
}

// gjk_distance() itself (public, for support types of any scale) takes |v|
// with scaling when |v|^2 is subnormal: the distance exact to rounding and
// v / distance a unit vector. (Its dot products lose bits down there too, so
// it may stop as stalled, with the same best-so-far answer; the queries of
// query.hpp never get there, see min_pair_extent.)
TEST(GjkHardCases, SubnormalSquaredDistanceInGjkDistance) {
  for (const double x : {8.2e-159, 3.0e-160, 1.0e-155, 1.0e-150}) {
    const Vec at = x * Vec(1, 2, -2).normalized();
    const PointCore origin;
    const Transformed<PointCore> moved{origin, Eigen::Matrix3d::Identity(), at};
    const GjkResult g = gjk_distance(origin, moved, Vec::UnitX(), 0.0);
    ASSERT_TRUE(g.status == GjkStatus::ok || g.status == GjkStatus::stalled) << x;
    ASSERT_FALSE(g.intersecting) << x;
    EXPECT_NEAR(g.distance, x, 4e-16 * x) << x;
    EXPECT_NEAR((g.v / g.distance).norm(), 1.0, 4e-16) << x;
  }
}

// Fuzz finding (derived from finding-epa-contradicting-gjk-on-a-needle): a
// sliver tetrahedron 2280 long and 1.7e-6 thick against a segment. In one
// order GJK's v left the Minkowski difference by 3.8e-7 and the distance
// came out 1.2774e-6, "ok" with a bound of 5e-8: the plane of a sliver
// triangle of the simplex, from a cross product whose rounding (eps L^2) is
// eps L / h of its length, tilted along the triangle. The exact distance is
// computed in rational arithmetic from the world vertices below (the
// differences a_i - b_j, the nearest point over all their triangles, edges
// and points); the family after it puts a point above the face of random
// needles of aspect 1e4..1e10 (1530 of 8000 answers outside their bound
// before; the distance is known by construction, the rounding of the posed
// vertices is in the slack).
TEST(GjkHardCases, SliverTrianglesKeepTheClosestPointOnTheDifference) {
  const double eps = std::numeric_limits<double>::epsilon();
  {
    const auto needle = make_hull({{-542.96875, 1.7375000000000001e-06, 1.7375000000000003e-06},
                                   {1737.5000000000005, 0, 0},
                                   {0, 0, 1.7375000000000003e-06},
                                   {1.7374999856656359e-06, 1.7375000000000001e-06, 1.7375000000000003e-06}});
    const auto segment =
        make_hull({{0, 0, 0}, {5.0000001000000019e-05, 5.0000001000000019e-05, 5.0000001000000019e-05}});
    const Pose pa = Pose::from_quaternion(Eigen::Quaterniond(4.9406564584124654e-315, 0, 0, 1), Vec(1e-9, 1e-9, 0));
    const Pose pb = Pose::from_quaternion(
        Eigen::Quaterniond(0.57735026918962562, 0.57735026918962606, 0.57735026918962606, 0), Vec(1e-9, 1e-9, 1e-9));
    // The world vertices this exact value was computed from.
    const std::vector<Vec> wa = world_vertices(*needle, pa), wb = world_vertices(*segment, pb);
    EXPECT_EQ(wa[1], Vec(-0x1.b25ffffffeed4p+10, 0x1.12e0be826d695p-30, 0.0));
    EXPECT_EQ(wb[1], Vec(0x1.5d878f94d4ac4p-14, 0x1.17a315aca55e7p-16, -0x1.179a7ea6b14bcp-16));
    const double exact = 1.6574544818578296e-06;
    const Shape a = Polyhedron{needle, 0.0}, b = Polyhedron{segment, 0.0};
    for (const bool swapped : {false, true}) {
      const DistanceResult d = swapped ? distance(b, pb, a, pa) : distance(a, pa, b, pb);
      ASSERT_EQ(d.status, Status::ok) << swapped;
      EXPECT_NEAR(d.distance, exact, d.error_bound + 64 * eps * 2280.0) << swapped;
    }
  }
  std::mt19937_64 rng(21);
  for (int i = 0; i < 4000; ++i) {
    const NeedleAndPoint c = needle_and_point_above_it(rng);
    const Shape needle = Polyhedron{make_hull(c.needle), 0.0};
    const Shape point = Sphere{0.0, 0.0};
    const Pose at = Pose::from_translation(c.point);
    for (const bool swapped : {false, true}) {
      const DistanceResult d =
          swapped ? distance(point, at, needle, Pose::identity()) : distance(needle, Pose::identity(), point, at);
      ASSERT_EQ(d.status, Status::ok) << i;
      if (d.intersecting) {
        // Touching within GJK's absolute tolerance (1e-10 of the size).
        EXPECT_LE(c.gap, 1e-10 * c.length + c.slack) << i;
      } else {
        EXPECT_NEAR(d.distance, c.gap, d.error_bound + c.slack) << i << " " << swapped;
      }
    }
  }
}

// Ground plates: flat cylinders and boxes 1e2 to 1e6 wide, 1e-3 thick, and
// small cones, cylinders and capsules a gap of 0.1 to 10 below them. Found
// by fuzzing: a cone 5.124 below a plate of radius 63 625 ended `stalled` at
// 5.125 (bound 1e-3) after two iterations, the step through a rim point at
// right angles lowering |v| by less than its rounding (2 of the 3000 random
// pairs below stalled the same way). Every distance ok, within 1e-10 of the
// plate's size of the gap (GJK's absolute tolerance).
TEST(GjkHardCases, SmallShapesUnderWideGroundPlatesConverge) {
  {
    const Shape plate = Cylinder{63625.0, 0.0005, 0.0}, cone = Cone{0.0006175, 0.0005, 0.0};
    const Pose pa = Pose::from_quaternion(Eigen::Quaterniond(0, 0, 0, 1), Vec(7.25, -1.0, 0.0));
    const Pose pb = Pose::from_translation(Vec(-6.375, -1.0625, -5.125));
    for (const bool swapped : {false, true}) {
      const DistanceResult d = swapped ? distance(cone, pb, plate, pa) : distance(plate, pa, cone, pb);
      ASSERT_EQ(d.status, Status::ok) << swapped;
      EXPECT_NEAR(d.distance, 5.124, d.error_bound + 1e-12 * 63625.0) << swapped;
      EXPECT_LE(d.error_bound, 1e-10 * 2.0 * 63625.0);
    }
  }
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const double width : {1e2, 1e3, 1e4, 1e5, 1e6}) {
    for (int kind = 0; kind < 3; ++kind) {
      for (int i = 0; i < 200; ++i) {
        const Shape plate = kind == 0   ? Shape(Cylinder{width, 5e-4, 0.0})
                            : kind == 1 ? Shape(Box{Vec(width, width, 5e-4), 0.0})
                                        : Shape(Box{Vec(width, 0.7 * width, 5e-4), 0.0});
        const Shape small = i % 3 == 0   ? Shape(Cone{0.3, 0.5, 0.0})
                            : i % 3 == 1 ? Shape(Cylinder{0.3, 0.5, 0.0})
                                         : Shape(Capsule{0.2, 0.5, 0.0});
        const double gap = 0.1 + 5.0 * (u(rng) + 1.0);
        const Pose pa = Pose::from_translation(Vec(u(rng), u(rng), u(rng)));
        const Eigen::Matrix3d rb =
            i % 2 == 1 ? Eigen::Matrix3d::Identity()
                       : Eigen::Matrix3d(Eigen::AngleAxisd(1e-3 * u(rng), Vec(u(rng), u(rng), 0.0).normalized()));
        // The small shape's highest point, gap below the plate's lower face.
        const double lateral = std::hypot(rb(2, 0), rb(2, 1));
        const double top = i % 3 == 0   ? std::max(0.5 * rb(2, 2), -0.5 * rb(2, 2) + 0.3 * lateral)
                           : i % 3 == 1 ? 0.5 * std::abs(rb(2, 2)) + 0.3 * lateral
                                        : 0.5 * std::abs(rb(2, 2)) + 0.2;
        Vec tb = pa.translation + Vec(0.1 * width * u(rng), 0.1 * width * u(rng), 0.0);
        tb.z() = pa.translation.z() - 5e-4 - gap - top;
        const Pose pb{rb, tb};
        const DistanceResult d = distance(plate, pa, small, pb);
        ASSERT_EQ(d.status, Status::ok) << width << " " << kind << " " << i;
        EXPECT_NEAR(d.distance, gap, 1e-10 * width) << width << " " << kind << " " << i;
      }
    }
  }
}

// area_vector() on slivers (aspect up to 1e12, far from the origin):
// orthogonal to every edge within rounding of the coordinates. (Without the
// projection off the longest edge, n . e_longest / |n| reaches eps L^2 / h.)
TEST(GjkSubAlgorithm, TriangleNormalOfASliverIsOrthogonalToItsEdges) {
  std::mt19937_64 rng(22);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const Vec along = random_unit(rng), across = along.unitOrthogonal();
    const Vec offset = 1e3 * random_unit(rng) * u(rng);
    const double length = 1e3 * u(rng) + 1.0;
    const double h = length * std::pow(10.0, -12.0 * u(rng));
    const std::array<Vec, 3> p = {offset - length * u(rng) * along, offset + length * u(rng) * along,
                                  offset + (length * (u(rng) - 0.5)) * along + h * across};
    const Vec n = area_vector(p[0], p[1], p[2]);
    ASSERT_GT(n.squaredNorm(), 0.0) << i;
    const double coordinates =
        std::max({p[0].cwiseAbs().maxCoeff(), p[1].cwiseAbs().maxCoeff(), p[2].cwiseAbs().maxCoeff()});
    for (int k = 0; k < 3; ++k) {
      const double off = std::abs(n.normalized().dot(p[(k + 1) % 3] - p[k])) / coordinates;
      worst = std::max(worst, off);
      ASSERT_LE(off, 16 * std::numeric_limits<double>::epsilon()) << i << " edge " << k;
    }
  }
  std::printf("worst |n . e| / coordinates: %.3g eps\n", worst / std::numeric_limits<double>::epsilon());
}

// s3d skips a face through the newest point when its coordinate's sign is
// certain beyond rounding (perf: most of the sub-algorithm's cost). On
// random tetrahedra not holding the origin, from well shaped to nearly
// flat, its point must be as near as the nearest point of all four faces.
TEST(GjkSubAlgorithm, TetrahedronSkipsOnlyFacesThatCannotBeNearest) {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int outside = 0, flat = 0;
  for (int i = 0; i < 20000; ++i) {
    std::array<Vec, 4> w;
    // Every fifth at 1e-105, where the determinants are subnormal.
    const double scale = i % 5 == 4 ? 1e-105 : 1.0;
    const Vec centre(3 * u(rng), 3 * u(rng), 3 * u(rng));
    const double squash = std::pow(10.0, -12.0 * (i % 7) / 6.0);  // 1 .. 1e-12
    for (Vec& p : w) p = scale * (centre + Vec(u(rng), u(rng), squash * u(rng)));
    gjk_detail::Sub sub;
    if (gjk_detail::s3d(w, sub)) continue;
    ++outside;
    flat += squash < 1e-6 ? 1 : 0;
    static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    double all = std::numeric_limits<double>::infinity();
    for (const auto& f : kFace) {
      gjk_detail::Sub face;
      gjk_detail::s2d(w, f[0], f[1], f[2], face, 3);
      all = std::min(all, face.point.squaredNorm());
    }
    ASSERT_LE(std::sqrt(sub.point.squaredNorm()), std::sqrt(all) + 1e-12 * scale * (centre.norm() + 2.0)) << i;
  }
  EXPECT_GT(outside, 10000);
  EXPECT_GT(flat, 3000);  // nearly flat ones among them
}

TEST(GjkStatus, CapInvalidInputAndNoNan) {
  GjkSettings capped;
  capped.max_iterations = 1;
  std::mt19937_64 rng(12);
  const auto h = make_hull(random_points(rng, 64, {1.0, 1.0, 1.0}));
  const DistanceResult r = distance(Polyhedron{h, 0.0}, random_pose(rng, 0.1), Cylinder{0.5, 0.5, 0.0},
                                    Pose::from_translation({3.0, 0.4, 0.2}), nullptr, capped);
  EXPECT_EQ(r.status, Status::max_iterations);  // never reported as separated/ok
  EXPECT_TRUE(std::isfinite(r.distance) && r.normal.allFinite());

  Pose nan_pose = Pose::identity();
  nan_pose.translation.x() = std::nan("");
  EXPECT_EQ(distance(Sphere{1.0, 0.0}, nan_pose, Sphere{1.0, 0.0}, Pose::identity()).status, Status::invalid_input);
  EXPECT_EQ(intersect(Sphere{-1.0, 0.0}, Pose::identity(), Sphere{1.0, 0.0}, Pose::identity()).status,
            Status::invalid_input);
  // Coincident centres (fcl#346): terminates at once, intersecting.
  const DistanceResult same = distance(Sphere{1.0, 0.0}, Pose::identity(), Sphere{1.0, 0.0}, Pose::identity());
  EXPECT_EQ(same.status, Status::ok);
  EXPECT_TRUE(same.intersecting);
  const DistanceResult cubes =
      distance(Box{{1, 1, 1}, 0.0}, Pose::identity(), Box{{1, 1, 1}, 0.0}, Pose::from_translation({1.9, 0, 0}));
  EXPECT_TRUE(cubes.intersecting);  // libccd#25: two 2 m cubes overlapping by 0.1
  EXPECT_EQ(cubes.status, Status::ok);
}

TEST(GjkAllocation, NoHeapAllocationPerQuery) {
  std::mt19937_64 rng(13);
  const std::vector<Shape> zoo = shape_zoo(rng);
  std::vector<Pose> poses;
  for (int i = 0; i < 64; ++i) poses.push_back(random_pose(rng, 1.5));
  GjkCache cache;
  double sink = 0.0;
  const long before = g_allocations.load();
  for (std::size_t i = 0; i < zoo.size(); ++i)
    for (std::size_t j = 0; j < zoo.size(); ++j)
      for (int k = 0; k < 8; ++k) {
        const Pose& pa = poses[(i * 8 + k) % poses.size()];
        const Pose& pb = poses[(j * 5 + k + 1) % poses.size()];
        sink += distance(zoo[i], pa, zoo[j], pb, &cache).distance;
        sink += intersect(zoo[i], pa, zoo[j], pb).intersecting ? 1.0 : 0.0;
      }
  const long after = g_allocations.load();
  EXPECT_EQ(after - before, 0);
  EXPECT_TRUE(std::isfinite(sink));
  // The counter does count: building a hull allocates.
  make_hull(random_points(rng, 10, {1, 1, 1}));
  EXPECT_GT(g_allocations.load(), after);
}

}  // namespace
}  // namespace hedra::collision
