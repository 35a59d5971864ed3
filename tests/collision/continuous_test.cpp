// Continuous queries (raycast, shape_cast, time_of_impact) against
// references independent of them:
//   - rays: the shapes' exact signed distance to a point, written here in
//     closed form (ball, box, and the meridian section of capsules,
//     cylinders and cones), or tools/reference for hulls; sphere tracing on
//     it (the distance is 1-Lipschitz in the point) brackets the first hit;
//   - casts and times of impact: tools/reference's exact signed distance of
//     the posed pair along the motion (poses from Eigen's slerp), traced with
//     the Lipschitz bound |v_rel| + theta_a r_a + theta_b r_b, brackets the
//     first contact [early, late]; a reported time after `late` by more than
//     the tolerance (in distance along the motion) is tunnelling;
//   - closed forms: a sphere against a sphere, a box falling onto a plate.
// Fixed seeds; the worst errors are printed.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exact_reference.hpp>
#include <hedra/collision/cast.hpp>
#include <hedra/collision/raycast.hpp>
#include <hedra/collision/time_of_impact.hpp>
#include <limits>
#include <random>
#include <vector>

namespace hedra::collision {
namespace {

using Vec = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

Vec random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Vec(g(rng), g(rng), g(rng)).normalized();
}

Quat random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Quat(g(rng), g(rng), g(rng), g(rng)).normalized();
}

std::shared_ptr<const ConvexPolyhedron> make_hull(const std::vector<Vec>& points) {
  ConvexPolyhedron::BuildResult built = ConvexPolyhedron::build(points);
  EXPECT_TRUE(built.ok()) << built.message;
  return built.polyhedron;
}

std::vector<Vec> random_points(std::mt19937_64& rng, int n, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  std::vector<Vec> p;
  for (int i = 0; i < n; ++i) p.emplace_back(u(rng), u(rng), u(rng));
  return p;
}

// ---- exact point distances (local frame), written independently -----------

// Signed distance of (x, y) to the convex polygon `poly` (counter-clockwise).
double polygon_sd(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  double outside = 0.0, depth = std::numeric_limits<double>::infinity(), closest = depth;
  bool inside = true;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d a = poly[i], b = poly[(i + 1) % poly.size()], e = b - a;
    const double len = e.norm();
    const double side = (e.x() * (p - a).y() - e.y() * (p - a).x()) / len;  // > 0 inside (left)
    if (side < 0.0) inside = false;
    depth = std::min(depth, side);
    const double s = std::clamp((p - a).dot(e) / (len * len), 0.0, 1.0);
    closest = std::min(closest, (a + s * e - p).norm());
  }
  (void)outside;
  return inside ? -depth : closest;
}

double point_sd(const Shape& shape, const Vec& q) {
  struct Visitor {
    const Vec& q;
    double meridian(const std::vector<Eigen::Vector2d>& section) const {
      return polygon_sd(section, Eigen::Vector2d(std::hypot(q.x(), q.y()), q.z()));
    }
    double operator()(const Sphere& s) const { return q.norm() - s.radius - s.margin; }
    double operator()(const Box& s) const {
      const Vec e = q.cwiseAbs() - s.half_extents;
      const double out = e.cwiseMax(0.0).norm();
      return (out > 0.0 ? out : e.maxCoeff()) - s.margin;
    }
    double operator()(const Capsule& s) const {
      const Vec axis(0.0, 0.0, std::clamp(q.z(), -s.half_length, s.half_length));
      return (q - axis).norm() - s.radius - s.margin;
    }
    double operator()(const Cylinder& s) const {
      const double r = s.radius, h = s.half_length;
      return meridian({{-r, -h}, {r, -h}, {r, h}, {-r, h}}) - s.margin;
    }
    double operator()(const Cone& s) const {
      const double r = s.radius, h = s.half_length;
      return meridian({{-r, -h}, {r, -h}, {0.0, h}}) - s.margin;
    }
    double operator()(const Polyhedron& s) const {
      const reference::ExactResult r =
          reference::exact_signed_distance(Shape(s), Pose::identity(), Sphere{0.0, 0.0}, Pose::from_translation(q));
      EXPECT_TRUE(r.ok) << r.reason;
      return r.distance;
    }
  };
  return std::visit(Visitor{q}, shape);
}

// The first t in [0, max] with sd(o + t d) <= 0, by sphere tracing from
// below (never above the true first hit); -1 when the trace leaves the ray.
double traced_hit(const Shape& shape, const Vec& o, const Vec& d, double max_fraction, double stop) {
  double t = 0.0;
  for (int k = 0; k < 100000; ++k) {
    const double sd = point_sd(shape, o + t * d);
    if (sd <= stop) return t;
    t += sd / d.norm();
    if (t > max_fraction) return -1.0;
  }
  return -2.0;
}

// ---- rays ----------------------------------------------------------------

struct RayFamily {
  const char* name;
  Shape shape;
  double size;   // bounding radius
  double depth;  // a point within 0.3 size of the centre is this deep (for the aim)
};

std::vector<RayFamily> ray_families(std::mt19937_64& rng) {
  std::vector<RayFamily> f;
  f.push_back({"sphere", Sphere{0.8, 0.2}, 1.0, 0.7});
  f.push_back({"box", Box{Vec(1.0, 0.5, 0.7), 0.0}, 1.4, 0.2});
  f.push_back({"rounded box", Box{Vec(1.0, 0.5, 0.7), 0.1}, 1.5, 0.3});
  f.push_back({"capsule", Capsule{0.8, 0.5, 0.05}, 1.35, 0.25});
  f.push_back({"cylinder", Cylinder{0.6, 0.9, 0.0}, 1.1, 0.3});
  f.push_back({"rounded cylinder", Cylinder{0.6, 0.9, 0.1}, 1.2, 0.4});
  f.push_back({"cone", Cone{0.9, 0.9, 0.0}, 1.3, 0.05});
  f.push_back({"rounded cone", Cone{0.9, 0.9, 0.05}, 1.35, 0.1});
  std::vector<Vec> pts = random_points(rng, 24, 1.0);
  f.push_back({"hull", Polyhedron{make_hull(pts), 0.0}, 1.8, 0.05});
  f.push_back({"rounded hull", Polyhedron{make_hull(pts), 0.1}, 1.9, 0.1});
  return f;
}

TEST(Raycast, MatchesTracedExactDistanceOnEveryShape) {
  std::mt19937_64 rng(20240522);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const RayFamily& fam : ray_families(rng)) {
    int hits = 0, misses = 0, tunnelled = 0;
    double worst = 0.0;
    const int rays = std::holds_alternative<Polyhedron>(fam.shape) ? 12 : 60;
    for (int i = 0; i < rays; ++i) {
      const Pose pose = Pose::from_quaternion(random_rotation(rng), Vec(u(rng), u(rng), u(rng)));
      const Vec origin = pose.translation + 4.0 * fam.size * random_unit(rng);
      // Half of the rays aim near the centre (deep inside), half anywhere.
      const Vec aim = pose.translation + (i % 2 == 0 ? 0.05 : 2.0) * fam.size * Vec(u(rng), u(rng), u(rng));
      const Vec direction = 1.5 * (aim - origin);
      const RaycastResult r = raycast(fam.shape, pose, origin, direction);
      ASSERT_NE(r.status, CastStatus::max_iterations) << fam.name << " ray " << i;
      ASSERT_NE(r.status, CastStatus::stalled) << fam.name << " ray " << i;
      const Vec o = pose.rotation.transpose() * (origin - pose.translation);
      const Vec d = pose.rotation.transpose() * direction;
      const double tol = 1e-9 * fam.size;
      const double traced = traced_hit(fam.shape, o, d, 1.0, 1e-13 * fam.size);
      if (i % 2 == 0) {
        ASSERT_GE(traced, 0.0) << fam.name << ": a ray through the centre misses";
      }
      if (!r.hit) {
        ++misses;
        // A miss: the ray never comes closer than the tolerance.
        EXPECT_TRUE(traced < 0.0 || point_sd(fam.shape, o + traced * d) > -tol) << fam.name << " ray " << i;
        continue;
      }
      ++hits;
      const double sd = point_sd(fam.shape, o + r.fraction * d);
      EXPECT_LE(sd, tol + 1e-12) << fam.name << " ray " << i;
      EXPECT_NEAR(r.normal.norm(), 1.0, 1e-12);
      if (traced < 0.0) continue;  // a graze within the tolerance
      // Rays through the centre enter at a slope >= depth / |aim - entry|:
      // the trace's stop is within 1e-13 size / slope of the true hit.
      const double error = (r.fraction - traced) * d.norm();
      if (i % 2 == 0) worst = std::max(worst, std::abs(error) / fam.size);
      if (i % 2 == 0 && error > tol * 4.0 * fam.size / fam.depth) ++tunnelled;
      // The normal is a supporting plane's at the hit: no point of the shape beyond it.
      const Vec n = pose.rotation.transpose() * r.normal;
      const Vec far = support(fam.shape, n);
      EXPECT_LE(n.dot(far - (o + r.fraction * d)), 2e-4 * fam.size) << fam.name << " ray " << i;
    }
    std::printf("raycast %-16s hits %3d misses %3d worst |fraction error| %.2e of the size, tunnelled %d\n", fam.name,
                hits, misses, worst, tunnelled);
    EXPECT_GE(hits, rays / 3) << fam.name;
    EXPECT_GT(misses, 0) << fam.name;
    EXPECT_EQ(tunnelled, 0) << fam.name;
    EXPECT_LE(worst, 1e-9) << fam.name;
  }
}

TEST(Raycast, ClosedFormsSphereBoxCapsuleCylinder) {
  // Sphere of radius 2 at (10, 0, 0), ray from the origin along x: t = 8.
  RaycastResult r = raycast(Sphere{1.5, 0.5}, Pose::from_translation(Vec(10, 0, 0)), Vec::Zero(), Vec(20, 0, 0));
  ASSERT_EQ(r.status, CastStatus::hit);
  EXPECT_NEAR(r.fraction, 0.4, 1e-15);
  EXPECT_NEAR((r.normal - Vec(-1, 0, 0)).norm(), 0.0, 1e-15);
  // Offset by 1 in y: enters at x = 10 - sqrt(3).
  r = raycast(Sphere{2.0, 0.0}, Pose::from_translation(Vec(10, 0, 0)), Vec(0, 1, 0), Vec(1, 0, 0), 100.0);
  EXPECT_NEAR(r.fraction, 10.0 - std::sqrt(3.0), 1e-14);
  // Box: a face, an edge (the ray along the face y = 0.5 and z = 0.7), a corner.
  const Box box{Vec(1.0, 0.5, 0.7), 0.0};
  r = raycast(box, Pose::identity(), Vec(-3, 0.2, 0.1), Vec(1, 0, 0), 10.0);
  EXPECT_EQ(r.status, CastStatus::hit);
  EXPECT_DOUBLE_EQ(r.fraction, 2.0);
  EXPECT_EQ(r.normal, Vec(-1, 0, 0));
  r = raycast(box, Pose::identity(), Vec(-3, 0.5, 0.7), Vec(1, 0, 0), 10.0);
  EXPECT_EQ(r.status, CastStatus::hit);
  EXPECT_DOUBLE_EQ(r.fraction, 2.0);
  r = raycast(box, Pose::identity(), Vec(-3, 0.5 + 1e-12, 0.7), Vec(1, 0, 0), 10.0);
  EXPECT_FALSE(r.hit);
  EXPECT_EQ(r.fraction, 10.0);
  r = raycast(box, Pose::identity(), Vec(-2, -1.5, -1.7), Vec(1, 1, 1), 10.0);
  EXPECT_EQ(r.status, CastStatus::hit);
  EXPECT_NEAR(r.fraction, 1.0, 1e-15);
  // The same box with a margin through GJK: the face moves out by the margin.
  r = raycast(Box{Vec(1.0, 0.5, 0.7), 0.25}, Pose::identity(), Vec(-3, 0.2, 0.1), Vec(1, 0, 0), 10.0);
  EXPECT_EQ(r.status, CastStatus::hit);
  EXPECT_NEAR(r.fraction, 1.75, 1e-9);
  EXPECT_NEAR((r.normal - Vec(-1, 0, 0)).norm(), 0.0, 1e-6);
  // Capsule: side at x = -radius, cap along the axis.
  const Capsule capsule{1.0, 0.5, 0.0};
  r = raycast(capsule, Pose::identity(), Vec(-5, 0, 0.3), Vec(1, 0, 0), 10.0);
  EXPECT_NEAR(r.fraction, 4.5, 1e-14);
  r = raycast(capsule, Pose::identity(), Vec(0, 0, 5), Vec(0, 0, -1), 10.0);
  EXPECT_NEAR(r.fraction, 3.5, 1e-14);
  EXPECT_NEAR((r.normal - Vec(0, 0, 1)).norm(), 0.0, 1e-14);
  // Cylinder: parallel to the axis onto the cap (through GJK), and onto the side.
  const Cylinder cylinder{0.5, 1.0, 0.0};
  r = raycast(cylinder, Pose::identity(), Vec(0.3, 0.2, 5), Vec(0, 0, -1), 10.0);
  ASSERT_EQ(r.status, CastStatus::hit);
  EXPECT_NEAR(r.fraction, 4.0, 1e-9);
  EXPECT_NEAR((r.normal - Vec(0, 0, 1)).norm(), 0.0, 1e-6);
  r = raycast(cylinder, Pose::identity(), Vec(0.5, 0, 5), Vec(0, 0, -1), 10.0);  // along the side's line
  ASSERT_EQ(r.status, CastStatus::hit);
  EXPECT_NEAR(r.fraction, 4.0, 1e-9);
  r = raycast(cylinder, Pose::identity(), Vec(0.5 + 1e-6, 0, 5), Vec(0, 0, -1), 10.0);  // just outside: misses
  EXPECT_FALSE(r.hit);
  r = raycast(cylinder, Pose::identity(), Vec(-3, 0.3, 0.2), Vec(1, 0, 0), 10.0);
  ASSERT_EQ(r.status, CastStatus::hit);
  EXPECT_NEAR(r.fraction, 3.0 - 0.4, 1e-9);
}

TEST(Raycast, FromInsideReportsFractionZero) {
  std::mt19937_64 rng(7);
  for (const RayFamily& fam : ray_families(rng)) {
    const Pose pose = Pose::from_translation(Vec(3e5, -2e5, 1e5));
    const RaycastResult r = raycast(fam.shape, pose, pose.translation + Vec(0.01, 0.02, 0.0), Vec(5, 1, 0));
    EXPECT_EQ(r.status, CastStatus::initially_overlapping) << fam.name;
    EXPECT_TRUE(r.hit && r.started_inside) << fam.name;
    EXPECT_EQ(r.fraction, 0.0) << fam.name;
  }
}

TEST(Raycast, FarFromTheOriginAndBadInput) {
  // The same ray 1e6 away hits within 1e-9 of the size where it hits near the origin.
  std::mt19937_64 rng(11);
  for (const RayFamily& fam : ray_families(rng)) {
    const Pose near_pose = Pose::from_quaternion(Quat(0.9, 0.1, 0.3, 0.2), Vec::Zero());
    const Vec origin(-3.0, 0.11, 0.13), direction(4.0, 0.0, 0.0);
    const RaycastResult near = raycast(fam.shape, near_pose, origin, direction);
    for (double far : {1e4, 1e5, 1e6}) {
      Pose far_pose = near_pose;
      far_pose.translation = Vec(far, -far, far);
      const RaycastResult r = raycast(fam.shape, far_pose, origin + far_pose.translation, direction);
      ASSERT_EQ(r.status, near.status) << fam.name << " at " << far;
      EXPECT_NEAR(r.fraction * 4.0, near.fraction * 4.0, 1e-9 * fam.size + 64e-16 * far) << fam.name << " at " << far;
    }
  }
  const Sphere s{1.0, 0.0};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(raycast(s, Pose::identity(), Vec(nan, 0, 0), Vec(1, 0, 0)).status, CastStatus::invalid_input);
  EXPECT_EQ(raycast(s, Pose::identity(), Vec(-5, 0, 0), Vec(1, 0, 0), -1.0).status, CastStatus::invalid_input);
  EXPECT_EQ(raycast(Sphere{-1.0, 0.0}, Pose::identity(), Vec(-5, 0, 0), Vec(1, 0, 0)).status,
            CastStatus::invalid_input);
  // A zero direction: a point, outside.
  const RaycastResult r = raycast(Cylinder{1, 1, 0}, Pose::identity(), Vec(-5, 0, 0), Vec::Zero());
  EXPECT_EQ(r.status, CastStatus::separated);
  EXPECT_FALSE(r.hit);
}

}  // namespace
}  // namespace hedra::collision
