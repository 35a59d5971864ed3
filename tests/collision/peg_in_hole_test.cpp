// Pegs in holes: a box, a random hull or a capsule deep inside a larger
// cylinder or cone, near its axis (revolution_polytope.hpp and the step
// that reaches it in penetration()):
//   * a small peg sees a ring of nearly equal depths (the hole's radius
//     plus a variation of the peg's size), which EPA's polytope cannot
//     resolve: every answer ok and within 1e-9 of the size of the exact
//     reference (tools/reference: its azimuth bracket, 1e-11 wide here),
//     both orders, margins on some;
//   * closed form: a box centred on a cylinder's axis, depth r + w;
//   * the branch and bound directly: an answer that hits its cap is honest.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <hedra/collision/detail/gjk.hpp>
#include <hedra/collision/detail/revolution_polytope.hpp>
#include <hedra/collision/query.hpp>
#include <random>

#include "collision_test_support.hpp"

namespace {

using namespace hedra::collision;
using namespace hedra::collision::testing;
using Vec = Eigen::Vector3d;

struct PegPair {
  Shape hole, peg;
  Pose hole_pose, peg_pose;
  double tilt = 0.0, offset = 0.0;
};

// Hole: a cylinder or cone (radius and half length 0.5 .. 1). Peg: a box, a
// random hull or a capsule, 1e-3 .. 0.3 of the hole's radius across and
// 0.1 .. 1.2 of its half length long (it may stick out), its axis `tilt`
// (1e-10 .. 1e-2 rad) off the hole's, its centre `offset` (1e-9 .. 1e-3 of
// the hole's size) from the axis; margins on a third of each.
PegPair peg_in_hole(std::mt19937_64& rng, int i) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  PegPair p;
  const double r = 0.5 + 0.5 * u(rng), h = 0.5 + 0.5 * u(rng);
  const bool cone = i % 2 == 1;
  const double hole_margin = u(rng) < 0.33 ? 0.05 * u(rng) : 0.0;
  if (cone)
    p.hole = Cone{r, h, hole_margin};
  else
    p.hole = Cylinder{r, h, hole_margin};
  const double across = r * std::pow(10.0, -3.0 + 2.5 * u(rng));
  const double w1 = across * (0.5 + 0.5 * u(rng)), w2 = across * (0.5 + 0.5 * u(rng));
  const double len = h * (0.1 + 1.1 * u(rng));
  const double peg_margin = u(rng) < 0.33 ? 0.2 * std::min(w1, w2) * u(rng) : 0.0;
  switch ((i / 2) % 3) {
    case 0:
      p.peg = Box{Vec(w1, w2, len), peg_margin};
      break;
    case 1: {
      const int n = 8 + static_cast<int>(24 * u(rng));
      p.peg = Polyhedron{make_hull(random_points(rng, n, Vec(w1, w2, len))), peg_margin};
      break;
    }
    default:
      p.peg = Capsule{w1, len, peg_margin};
  }
  p.tilt = std::pow(10.0, -10.0 + 8.0 * u(rng));
  p.offset = std::pow(10.0, -9.0 + 6.0 * u(rng));
  const double size = std::max(r, h);
  const Eigen::Matrix3d base = Eigen::Quaterniond{g(rng), g(rng), g(rng), g(rng)}.normalized().toRotationMatrix();
  const double spin = 2.0 * M_PI * u(rng), turn = 2.0 * M_PI * u(rng), side = 2.0 * M_PI * u(rng);
  const Vec tilt_axis(std::cos(turn), std::sin(turn), 0.0), side_dir(std::cos(side), std::sin(side), 0.0);
  const Eigen::Matrix3d peg_rotation = Eigen::AngleAxisd(p.tilt, tilt_axis).toRotationMatrix() *
                                       Eigen::AngleAxisd(spin, Vec::UnitZ()).toRotationMatrix();
  // Axially: a cylinder's peg anywhere in its middle, a cone's in its wide half.
  const double z = cone ? -h * 0.5 * u(rng) : h * (-0.3 + 0.6 * u(rng));
  const Vec centre = 2.0 * Vec(g(rng), g(rng), g(rng));
  p.hole_pose = Pose{base, centre};
  p.peg_pose = Pose{base * peg_rotation, centre + base * (p.offset * size * side_dir + Vec(0.0, 0.0, z))};
  return p;
}

TEST(PegInHole, SmallPegsSeeARingOfNearlyEqualDepthsAndAreStillExact) {
  std::mt19937_64 rng(20);
  hedra::reference::ExactSettings tight;
  tight.target_width = 1e-11;
  tight.max_azimuth_evaluations = 400000;
  int checked = 0;
  double worst = 0.0, widest = 0.0;
  for (int i = 0; i < 72; ++i) {
    const PegPair p = peg_in_hole(rng, i);
    const double size = std::max(bounding_radius(p.hole), bounding_radius(p.peg));
    const hedra::reference::ExactResult ref =
        hedra::reference::exact_signed_distance(p.hole, p.hole_pose, p.peg, p.peg_pose, tight);
    ASSERT_TRUE(ref.ok) << ref.reason;
    // The reference judges to 1e-9 only with a bracket well within it.
    EXPECT_LE(ref.upper - ref.lower, 1e-10 * size) << i;
    widest = std::max(widest, (ref.upper - ref.lower) / size);
    for (const bool swap : {false, true}) {
      const PenetrationResult r = swap ? penetration(p.peg, p.peg_pose, p.hole, p.hole_pose)
                                       : penetration(p.hole, p.hole_pose, p.peg, p.peg_pose);
      const double error = std::max({0.0, ref.lower - r.distance, r.distance - ref.upper});
      worst = std::max(worst, error / size);
      EXPECT_EQ(r.status, Status::ok) << i << " swap " << swap << " tilt " << p.tilt << " offset " << p.offset;
      EXPECT_LE(error, 1e-9 * size) << i << " swap " << swap << " tilt " << p.tilt << " offset " << p.offset;
      EXPECT_LE(r.error_bound, 1e-10 * std::max(std::abs(r.distance), size)) << i;
      EXPECT_NEAR(r.normal.norm(), 1.0, 1e-12) << i;
      EXPECT_LT((r.point_b - r.point_a - r.distance * r.normal).norm(), 1e-12 * size) << i;
      // Witnesses on both support planes.
      const Shape& a = swap ? p.peg : p.hole;
      const Shape& b = swap ? p.hole : p.peg;
      const Pose& pa = swap ? p.peg_pose : p.hole_pose;
      const Pose& pb = swap ? p.hole_pose : p.peg_pose;
      EXPECT_NEAR(r.normal.dot(r.point_a), support_value(a, pa, r.normal), 1e-9 * size) << i << " swap " << swap;
      EXPECT_NEAR(-r.normal.dot(r.point_b), support_value(b, pb, -r.normal), 1e-9 * size) << i << " swap " << swap;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 144);
  std::printf("worst error %.2e of the size; widest reference bracket %.2e\n", worst, widest);
}

// A box of half extents (w, w, L) centred on the axis of a cylinder of
// radius r (r + w below the axial depth): depth r + w exactly, over a ring
// where the box's faces are only w r apart from its edges' directions.
TEST(PegInHole, ABoxCentredOnACylindersAxisIsAsDeepAsRadiusPlusHalfWidth) {
  std::mt19937_64 rng(3);
  for (double w = 1e-4; w <= 1e-1; w *= 10.0) {
    const Cylinder hole{0.8, 1.0, 0.0};
    const Box peg{Vec(w, w, 0.9), 0.0};
    const Eigen::Matrix3d ra = Eigen::AngleAxisd(1.0, random_unit(rng)).toRotationMatrix();
    const Pose pa{ra, Vec(0.3, -0.2, 0.1)};
    const Pose pb{ra * Eigen::AngleAxisd(0.3, Vec::UnitZ()).toRotationMatrix(), pa.translation};
    for (const bool swap : {false, true}) {
      const PenetrationResult r = swap ? penetration(peg, pb, hole, pa) : penetration(hole, pa, peg, pb);
      EXPECT_EQ(r.status, Status::ok) << w;
      EXPECT_NEAR(r.distance, -(0.8 + w), r.error_bound + 1e-13) << w;
      EXPECT_LE(r.error_bound, 1e-10 * std::hypot(0.8, 1.0)) << w;
    }
  }
}

// Directly, with a small cap: the bracket stays honest (the reference's
// value inside it) whatever the status.
TEST(PegInHole, TheBranchAndBoundIsHonestAtItsCap) {
  std::mt19937_64 rng(11);
  int capped = 0;
  for (int i = 0; i < 24; ++i) {
    const PegPair p = peg_in_hole(rng, i % 2);  // a box in a cylinder or a cone
    const Box& box = std::get<Box>(p.peg);
    const BoxCore core_b{box.half_extents};
    const RelativePose rel = relative_pose(p.hole_pose, Vec::Zero(), p.peg_pose, Vec::Zero());
    const double scale = std::max(bounding_radius(p.hole), bounding_radius(p.peg));
    RevolutionPolytopeSettings small;
    small.max_intervals = 40;
    EpaResult q;
    bool known = false;
    if (const auto* c = std::get_if<Cylinder>(&p.hole))
      known = revolution_polytope_penetration(CylinderCore{c->radius, c->half_length}, core_b, rel, scale, nullptr, 0,
                                              EpaSettings{}, q, small);
    else if (const auto* c = std::get_if<Cone>(&p.hole))
      known = revolution_polytope_penetration(ConeCore{c->radius, c->half_length}, core_b, rel, scale, nullptr, 0,
                                              EpaSettings{}, q, small);
    ASSERT_TRUE(known) << i;
    Shape hole_core = p.hole, peg_core = Box{box.half_extents, 0.0};
    std::visit([](auto& s) { s.margin = 0.0; }, hole_core);
    const hedra::reference::ExactResult ref =
        hedra::reference::exact_signed_distance(hole_core, p.hole_pose, peg_core, p.peg_pose);
    ASSERT_TRUE(ref.ok);
    if (q.status == EpaStatus::max_iterations) ++capped;
    EXPECT_TRUE(q.status == EpaStatus::ok || q.status == EpaStatus::max_iterations) << i;
    EXPECT_GE(-ref.lower, q.depth - q.error_bound - 1e-12 * scale) << i;  // depth = -sd
    EXPECT_LE(-ref.upper, q.depth + 1e-12 * scale) << i;
  }
  EXPECT_GE(capped, 1);
}

}  // namespace
