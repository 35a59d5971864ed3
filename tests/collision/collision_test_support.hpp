// Helpers shared by the collision tests: hull construction, seeded random
// points and directions, world-frame vertices, and support values of posed
// shapes (for optimality checks of witness points and normals).
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <hedra/collision/minkowski.hpp>
#include <hedra/collision/shapes.hpp>
#include <hedra/collision/support.hpp>
#include <memory>
#include <random>
#include <vector>

namespace hedra::collision::testing {

using Vec = Eigen::Vector3d;

inline std::shared_ptr<const ConvexPolyhedron> make_hull(const std::vector<Vec>& points) {
  ConvexPolyhedron::BuildResult built = ConvexPolyhedron::build(points);
  EXPECT_TRUE(built.ok()) << built.message;
  return built.polyhedron;
}

inline Vec random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Vec(g(rng), g(rng), g(rng)).normalized();
}

// n points uniform in the box [-scale, scale].
inline std::vector<Vec> random_points(std::mt19937_64& rng, int n, const Vec& scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec> p;
  for (int i = 0; i < n; ++i) p.push_back(Vec(u(rng), u(rng), u(rng)).cwiseProduct(scale));
  return p;
}

inline std::vector<Vec> posed(const std::vector<Vec>& local, const Pose& pose) {
  std::vector<Vec> out;
  for (const Vec& v : local) out.push_back(pose.apply(v));
  return out;
}

// A polyhedron's vertices in the world frame (it stores them recentred).
inline std::vector<Vec> world_vertices(const ConvexPolyhedron& poly, const Pose& pose) {
  std::vector<Vec> out;
  for (const Vec& v : poly.vertices()) out.push_back(pose.apply(poly.offset() + v));
  return out;
}

// max over the posed shape of n . x.
inline double support_value(const Shape& s, const Pose& pose, const Vec& n) {
  return n.dot(pose.apply(support(s, pose.rotation.transpose() * n)));
}

}  // namespace hedra::collision::testing
