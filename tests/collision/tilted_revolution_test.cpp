// The branch and bound over directions for cores of revolution
// (tilted_revolution.hpp), through penetration() and directly:
//   * certified: no direction found by an independent search (support
//     values of the shapes themselves, not the profiles: a scan of both kink
//     circles, random directions, pattern-search refinement) separates the
//     pair by more than the answer's upper end, and the answer is itself a
//     support value (-h_D along its normal);
//   * tight: status ok, bound within the EPA tolerance, the answer within
//     1e-9 of the best direction found (before, on nearly coaxial cylinders
//     and cones: polytope_full, within 2 theta R of it);
//   * closed form: coincident cylinders, any small tilt: depth r_A + r_B;
//   * witnesses on the shapes, on their support planes;
//   * any tilt, directly: agrees with EPA where EPA converged, and an answer
//     that hits the square cap is still honest.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <hedra/collision/detail/gjk.hpp>
#include <hedra/collision/detail/tilted_revolution.hpp>
#include <hedra/collision/query.hpp>
#include <random>

#include "collision_test_support.hpp"

namespace {

using namespace hedra::collision;
using namespace hedra::collision::testing;
using Vec = Eigen::Vector3d;

double separation(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb, const Vec& n) {
  return -(support_value(a, pa, n) + support_value(b, pb, -n));
}

// The best separation (a lower bound of the signed distance) over the kink
// circles of both axes and 500 random directions, the best 4 refined by a
// pattern search on the sphere.
double best_separation(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb, std::mt19937_64& rng) {
  double best = lower_bound_over_great_circles(a, pa, b, pb, {Vec(pa.rotation.col(2)), Vec(pb.rotation.col(2))});
  std::vector<std::pair<double, Vec>> seeds;
  for (int i = 0; i < 500; ++i) {
    const Vec n = random_unit(rng);
    seeds.push_back({separation(a, pa, b, pb, n), n});
  }
  std::partial_sort(seeds.begin(), seeds.begin() + 4, seeds.end(),
                    [](const auto& x, const auto& y) { return x.first > y.first; });
  for (int s = 0; s < 4; ++s) {
    Vec n = seeds[s].second;
    double value = seeds[s].first;
    for (double step = 0.1; step > 1e-13; step *= 0.5) {
      bool moved = true;
      while (moved) {
        moved = false;
        const Vec e1 = n.unitOrthogonal(), e2 = n.cross(e1);
        for (const Vec& d : {e1, e2, Vec(-e1), Vec(-e2), Vec(e1 + e2), Vec(e1 - e2), Vec(-e1 + e2), Vec(-e1 - e2)}) {
          const Vec m = (n + step * d).normalized();
          const double v = separation(a, pa, b, pb, m);
          if (v > value) {
            value = v;
            n = m;
            moved = true;
          }
        }
      }
    }
    best = std::max(best, value);
  }
  return best;
}

// p in the (posed) cylinder or cone, up to tol.
bool inside(const Shape& s, const Pose& pose, const Vec& p, double tol) {
  const Vec q = pose.rotation.transpose() * (p - pose.translation);
  const double radial = std::hypot(q.x(), q.y());
  if (const auto* c = std::get_if<Cylinder>(&s))
    return std::abs(q.z()) <= c->half_length + tol && radial <= c->radius + tol;
  if (const auto* c = std::get_if<Cone>(&s))
    return std::abs(q.z()) <= c->half_length + tol &&
           radial <= c->radius * (c->half_length - q.z()) / (2.0 * c->half_length) + tol;
  return true;
}

struct Pair {
  Shape a, b;
  Pose pa, pb;
  double tilt = 0.0;
};

// A cylinder or cone A, a cylinder, cone or capsule B (sizes 0.2 .. 1),
// B's axis tilt (1e-10 .. 1e-2 rad) off A's, parallel or anti-parallel,
// centres 0 .. 0.3 of A's size apart.
Pair nearly_coaxial_pair(std::mt19937_64& rng, int i) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  const auto size = [&] { return 0.2 + 0.8 * u(rng); };
  Pair p;
  p.a = i % 2 == 0 ? Shape(Cylinder{size(), size(), 0.0}) : Shape(Cone{size(), size(), 0.0});
  switch (i % 3) {
    case 0:
      p.b = Cylinder{size(), size(), 0.0};
      break;
    case 1:
      p.b = Cone{size(), size(), 0.0};
      break;
    default:
      p.b = Capsule{size(), 0.3 * size(), 0.0};
  }
  p.tilt = std::pow(10.0, -10.0 + 8.0 * u(rng));
  const Eigen::Matrix3d ra = Eigen::Quaterniond{g(rng), g(rng), g(rng), g(rng)}.normalized().toRotationMatrix();
  Eigen::Matrix3d rb = ra * Eigen::AngleAxisd(p.tilt, random_unit(rng)).toRotationMatrix();
  if (i % 5 == 4) rb = rb * Eigen::AngleAxisd(M_PI, Vec::UnitX()).toRotationMatrix();  // anti-parallel
  const double offset = (i % 4 == 0) ? 0.0 : 0.3 * std::pow(u(rng), 3.0);
  p.pa = Pose{ra, Vec::Zero()};
  p.pb = Pose{rb, offset * bounding_radius(p.a) * random_unit(rng)};
  return p;
}

TEST(TiltedRevolution, NearlyCoaxialPairsAreCertifiedAndTight) {
  std::mt19937_64 rng(2026);
  int checked = 0;
  for (int i = 0; i < 80; ++i) {
    const Pair p = nearly_coaxial_pair(rng, i);
    const PenetrationResult r = penetration(p.a, p.pa, p.b, p.pb);
    if (!r.intersecting) continue;
    ++checked;
    const double scale = std::max(bounding_radius(p.a), bounding_radius(p.b));
    const double found = best_separation(p.a, p.pa, p.b, p.pb, rng);
    const double slack = 1e-13 * scale;
    EXPECT_EQ(r.status, Status::ok) << i << " tilt " << p.tilt;
    // EPA's tolerance: relative to the depth, absolute to the size.
    EXPECT_LE(r.error_bound, 1e-10 * std::max(std::abs(r.distance), scale) + slack) << i << " tilt " << p.tilt;
    // Certified: no direction separates by more than the upper end.
    EXPECT_GE(r.distance + r.error_bound, found - slack)
        << i << " tilt " << p.tilt << " excess " << found - r.distance - r.error_bound << " epa " << r.epa_iterations;
    // Tight: as good as the best direction the search found.
    EXPECT_LE(found - r.distance, 1e-9 * scale) << i << " tilt " << p.tilt;
    // The separation along the normal is within the bound of the answer
    // (equal for the branch and bound's, a support value; EPA's is its
    // polytope's face, the lower end, its bound from supports in A's frame:
    // up to 9e-11 off in the world frame here).
    EXPECT_NEAR(separation(p.a, p.pa, p.b, p.pb, r.normal), r.distance, r.error_bound + 1e-10 * scale)
        << i << " tilt " << p.tilt;
    EXPECT_LT((r.point_b - r.point_a - r.distance * r.normal).norm(), 1e-12 * scale) << i;
    if (!std::holds_alternative<Capsule>(p.b)) {
      const double tol = 1e-8 * scale;
      EXPECT_TRUE(inside(p.a, p.pa, r.point_a, tol)) << i;
      EXPECT_TRUE(inside(p.b, p.pb, r.point_b, tol)) << i;
      EXPECT_NEAR(r.normal.dot(r.point_a), support_value(p.a, p.pa, r.normal), tol) << i;
      EXPECT_NEAR(-r.normal.dot(r.point_b), support_value(p.b, p.pb, -r.normal), tol) << i;
    }
  }
  EXPECT_GE(checked, 60);
}

// Coincident centres: the depth is r_A + r_B exactly at every small tilt
// (the sides, along a x b, where both support functions are flat to first
// order; the caps are deeper).
TEST(TiltedRevolution, CoincidentCylindersHaveTheSumOfTheirRadiiAsDepth) {
  std::mt19937_64 rng(5);
  const Cylinder a{0.5, 0.7, 0.0}, b{0.4, 0.6, 0.0};
  for (double tilt = 1e-10; tilt <= 1e-2; tilt *= 3.0) {
    const Eigen::Matrix3d ra = Eigen::AngleAxisd(1.0, random_unit(rng)).toRotationMatrix();
    const Pose pa{ra, Vec::Zero()};
    const Pose pb{ra * Eigen::AngleAxisd(tilt, random_unit(rng)).toRotationMatrix(), Vec::Zero()};
    const PenetrationResult r = penetration(a, pa, b, pb);
    EXPECT_EQ(r.status, Status::ok) << tilt;
    EXPECT_NEAR(r.distance, -0.9, 1e-10) << tilt;
    EXPECT_LE(r.error_bound, 1e-10) << tilt;
  }
}

// A small core (wider than long) centred deep inside a large cylinder whose
// radius equals its half length, axes 1e-9 .. 1e-3 rad apart (found by
// fuzzing: such pairs ended polytope_full). The depth along A's axis is
// within the small core's size of the radial one, so EPA cannot certify
// it, and the minimum lies at a pole, where the disc coordinates cannot
// resolve directions: the cap bound there (pole_cap_bound) must. Closed
// form: for n at angle phi from A's axis h_A(n) = 0.105 (cos phi + sin phi),
// at least 0.105, growing at rate 0.105 from the pole while B's part falls
// at most at the rate of its size, and B's support value is at least its
// half length (shorter than its radius) everywhere: the minimum is at the
// poles, the lower of h_A(+-a) + h_B(-+a).
TEST(TiltedRevolution, SmallCoresDeepInALargeCylinderAreCertifiedAtItsCap) {
  std::mt19937_64 rng(9);
  const Cylinder a{0.105, 0.105, 0.0};
  const std::array<Shape, 3> small = {Shape(Cylinder{1.05e-4, 5e-6, 0.0}), Shape(Cone{8e-5, 2e-5, 0.0}),
                                      Shape(Cylinder{3e-4, 1e-5, 0.0})};
  int checked = 0;
  for (double tilt = 1e-9; tilt <= 1e-3; tilt *= 10.0) {
    for (const Shape& b : small) {
      for (const bool flip : {false, true}) {
        const Eigen::Matrix3d ra = Eigen::AngleAxisd(2.0, random_unit(rng)).toRotationMatrix();
        Eigen::Matrix3d rb = ra * Eigen::AngleAxisd(tilt, random_unit(rng)).toRotationMatrix();
        if (flip) rb = rb * Eigen::AngleAxisd(M_PI, Vec::UnitX()).toRotationMatrix();
        const Vec centre = 3.0 * random_unit(rng);
        const Pose pa{ra, centre}, pb{rb, centre};
        const Vec axis = ra.col(2);
        const double exact = std::max(separation(Shape(a), pa, b, pb, axis), separation(Shape(a), pa, b, pb, -axis));
        const PenetrationResult r = penetration(Shape(a), pa, b, pb);
        EXPECT_EQ(r.status, Status::ok) << tilt;
        EXPECT_NEAR(r.distance, exact, 1e-10 * 0.15) << tilt;
        EXPECT_LE(r.error_bound, 1e-10 * 0.15) << tilt;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 42);
}

// Directly, at any tilt: the same answer as EPA where EPA converged (both
// certified, so their intervals overlap), and honest when the cap is hit.
TEST(TiltedRevolution, AgreesWithEpaAtAnyTilt) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int compared = 0;
  for (int i = 0; i < 300; ++i) {
    const CylinderCore ca{0.2 + 0.8 * u(rng), 0.2 + 0.8 * u(rng)};
    const ConeCore cb{0.2 + 0.8 * u(rng), 0.2 + 0.8 * u(rng)};
    RelativePose rel;
    rel.rotation = Eigen::AngleAxisd(M_PI * u(rng), random_unit(rng)).toRotationMatrix();
    rel.translation = 0.8 * u(rng) * random_unit(rng);
    const double scale = std::max(ca.bounding_radius(), cb.bounding_radius());
    const Transformed<ConeCore> placed{cb, rel.rotation, rel.translation};
    const GjkResult g = gjk_distance(ca, placed, Vec(-rel.translation), scale, GjkSettings{});
    if (!g.intersecting) continue;
    const EpaResult e = epa_penetration(ca, placed, g.simplex, scale, rel.translation, EpaSettings{});
    EpaResult q;
    TiltedRevolutionSettings small;
    small.max_squares = 256;
    ASSERT_TRUE(tilted_revolution_penetration(ca, cb, rel, scale, &rel.translation, 1, EpaSettings{}, q, small));
    EXPECT_TRUE(q.status == EpaStatus::ok || q.status == EpaStatus::max_iterations) << i;
    EXPECT_TRUE(std::isfinite(q.depth) && std::isfinite(q.error_bound) && q.normal.allFinite()) << i;
    EXPECT_NEAR(q.normal.norm(), 1.0, 1e-12) << i;
    if (e.status != EpaStatus::ok) continue;
    ++compared;
    EXPECT_NEAR(q.depth, e.depth, q.error_bound + e.error_bound + 1e-14 * scale)
        << i << " " << to_string(q.status) << " squares " << q.iterations;
    // The branch and bound's depth is a support value, EPA's the face of
    // its polytope: [e.depth, e.depth + bound] and [q.depth - bound,
    // q.depth] both hold the true depth.
    EXPECT_GE(q.depth, e.depth - 1e-14 * scale) << i;
    EXPECT_GE(e.depth + e.error_bound, q.depth - q.error_bound - 1e-14 * scale) << i;
  }
  EXPECT_GE(compared, 100);
}

}  // namespace
