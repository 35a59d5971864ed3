// Hard-case families not covered elsewhere, against the exact reference
// (qhull on conv{a_i - b_j}) where one exists:
//   * 10 000-vertex hulls (points on an ellipsoid) against a small box and a
//     tetrahedron: distance and penetration depth (the Minkowski difference
//     of two large hulls is too big for qhull, so the partner stays small).
// Fixed seeds; zero failures, zero NaN.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <hedra/collision/query.hpp>
#include <qhull_reference.hpp>
#include <random>
#include <vector>

#include "collision_test_support.hpp"

namespace hedra::collision {
namespace {

using namespace hedra::collision::testing;

using Vec = Eigen::Vector3d;

// Signed distance from the origin to the boundary of conv{a_i - b_j}:
// positive outside (the distance), negative inside (minus the depth, the
// smallest facet offset).
double reference_signed_distance(const std::vector<Vec>& a, const std::vector<Vec>& b) {
  std::vector<Vec> diff;
  for (const Vec& p : a)
    for (const Vec& q : b) diff.push_back(p - q);
  const reference::QhullHull h = reference::qhull_hull(diff, "Qt");
  EXPECT_TRUE(h.ok) << h.messages;
  double smallest_offset = INFINITY, outside_distance = INFINITY;
  bool outside = false;
  for (const auto& t : h.triangles) {
    const Vec &p0 = diff[t[0]], &p1 = diff[t[1]], &p2 = diff[t[2]];
    const Vec n = (p1 - p0).cross(p2 - p0).normalized();
    const double offset = n.dot(p0);
    smallest_offset = std::min(smallest_offset, offset);
    if (offset < 0.0) outside = true;
    // Distance from the origin to the triangle: clamp to edges or interior.
    const Vec q = offset * n;
    const bool inside = n.dot((p1 - p0).cross(q - p0)) >= 0.0 && n.dot((p2 - p1).cross(q - p1)) >= 0.0 &&
                        n.dot((p0 - p2).cross(q - p2)) >= 0.0;
    double d = inside ? std::abs(offset) : INFINITY;
    for (const auto& [x, y] : {std::pair{p0, p1}, std::pair{p1, p2}, std::pair{p2, p0}}) {
      const Vec e = y - x;
      const double s = std::clamp(-x.dot(e) / e.squaredNorm(), 0.0, 1.0);
      d = std::min(d, (x + s * e).norm());
    }
    outside_distance = std::min(outside_distance, d);
  }
  return outside ? outside_distance : -smallest_offset;
}

TEST(HardCases, TenThousandVertexHullAgainstSmallPolytopes) {
  std::mt19937_64 rng(501);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec> points;
  for (int i = 0; i < 10000; ++i)
    points.push_back(Vec(g(rng), g(rng), g(rng)).normalized().cwiseProduct(Vec(1.0, 0.8, 0.6)));
  const ConvexPolyhedron::BuildResult built = ConvexPolyhedron::build(points);
  ASSERT_TRUE(built.ok()) << built.message;
  const auto big = built.polyhedron;
  ASSERT_GT(big->vertex_count(), 9000u);
  std::vector<Vec> big_points;
  for (const Vec& v : big->vertices()) big_points.push_back(big->offset() + v);
  const Box box{{0.05, 0.08, 0.03}, 0.0};
  const std::vector<Vec> tetra = {{0.1, 0, 0}, {0, 0.1, 0}, {0, 0, 0.1}, {-0.05, -0.05, -0.05}};
  const ConvexPolyhedron::BuildResult tb = ConvexPolyhedron::build(tetra);
  ASSERT_TRUE(tb.ok());
  std::vector<Vec> box_points;
  for (int k = 0; k < 8; ++k) box_points.emplace_back(k & 1 ? 0.05 : -0.05, k & 2 ? 0.08 : -0.08, k & 4 ? 0.03 : -0.03);
  const double size = big->bounding_radius();
  int separated = 0, penetrating = 0;
  double worst = 0.0;
  for (int i = 0; i < 24; ++i) {
    const bool use_box = i % 2 == 0;
    const Shape small = use_box ? Shape(box) : Shape(Polyhedron{tb.polyhedron, 0.0});
    const std::vector<Vec>& small_local = use_box ? box_points : tetra;
    // Around the ellipsoid's surface: from 0.1 inside to 0.1 outside.
    const Vec dir = Vec(g(rng), g(rng), g(rng)).normalized();
    const double along = support(Polyhedron{big, 0.0}, dir).dot(dir) + 0.1 * u(rng);
    const Pose pb = Pose::from_quaternion(Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)), along * dir);
    const double expected = reference_signed_distance(big_points, posed(small_local, pb));
    const PenetrationResult p = penetration(Polyhedron{big, 0.0}, Pose::identity(), small, pb);
    ASSERT_EQ(p.status, Status::ok) << i;
    ASSERT_TRUE(std::isfinite(p.distance) && p.normal.allFinite()) << i;
    EXPECT_NEAR(p.distance, expected, 1e-9 * size) << i;
    worst = std::max(worst, std::abs(p.distance - expected) / size);
    const DistanceResult d = distance(Polyhedron{big, 0.0}, Pose::identity(), small, pb);
    ASSERT_EQ(d.status, Status::ok) << i;
    if (expected > 1e-9 * size) {
      ++separated;
      EXPECT_NEAR(d.distance, expected, 1e-9 * size) << i;
    } else if (expected < -1e-9 * size) {
      ++penetrating;
      EXPECT_TRUE(d.intersecting) << i;
    }
  }
  EXPECT_GT(separated, 4);
  EXPECT_GT(penetrating, 4);
  RecordProperty("worst_error_over_size", std::to_string(worst));
}

}  // namespace
}  // namespace hedra::collision
