// The embedding API: queries between two posed shapes.
//
//   intersect(a, pose_a, b, pose_b)        do they overlap or touch? (GJK,
//                                          stops at the first separating axis)
//   distance(a, pose_a, b, pose_b, cache)  distance, unit normal from A toward
//                                          B and world witness points
//   penetration(...)                       depth, normal and witnesses of
//                                          overlapping shapes: EPA, the next
//                                          step of issue 3 (not yet written;
//                                          it will start from the GJK simplex
//                                          that distance() ends with).
//
// How a query runs: one std::visit on the pair of shapes picks fully typed
// code; each shape splits into core + radius (minkowski.hpp); B's core is
// placed in A's core frame (relative_pose), GJK runs on the cores with no
// virtual call and no allocation, and the radii are added analytically:
//   distance = core distance - r_a - r_b,
//   point_a  = core point_a + r_a n,   point_b = core point_b - r_b n,
// with n the unit normal from A toward B. Results return to world
// coordinates at the end (point_b - point_a = distance * normal up to the
// rounding of the world coordinates).
//
// Threads: shapes are immutable and the per-query state lives on the stack
// or in the caller's cache, so many threads may query shared shapes, each
// with its own caches.
#pragma once

#include <Eigen/Core>
#include <hedra/collision/gjk.hpp>
#include <hedra/collision/minkowski.hpp>
#include <hedra/collision/shapes.hpp>

namespace hedra::collision {

enum class Status {
  ok,              // outputs valid
  max_iterations,  // GJK hit its cap: outputs are the best so far, no verdict
  degenerate,      // a non-finite support point appeared
  invalid_input,   // a shape failed validate() or a pose is not finite
};

const char* to_string(Status status);

struct IntersectResult {
  Status status = Status::ok;
  bool intersecting = false;  // meaningful only when status == ok
  int iterations = 0;
};

struct DistanceResult {
  Status status = Status::ok;
  bool intersecting = false;  // the shapes overlap or touch (then distance = 0)
  double distance = 0.0;      // >= 0
  // Unit normal from A toward B and the closest points, world frame; valid
  // when status == ok and !intersecting (zero otherwise: penetration() is the
  // query for overlapping shapes).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();
  // Certified upper bound on (distance - true distance), from the duality gap.
  double error_bound = 0.0;
  int iterations = 0;
};

// `cache` (optional): per-pair warm start, updated by the call. Keep one per
// pair (and per thread); a cache used with another pair only costs speed.
IntersectResult intersect(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                          GjkCache* cache = nullptr, const GjkSettings& settings = {});

DistanceResult distance(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                        GjkCache* cache = nullptr, const GjkSettings& settings = {});

}  // namespace hedra::collision
