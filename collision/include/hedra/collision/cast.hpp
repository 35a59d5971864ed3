// Shape cast: two shapes translating (no rotation) over a step.
//
//   shape_cast(a, pose_a, translation_a, b, pose_b, translation_b, cache, settings)
//
// A moves from pose_a to pose_a + translation_a, B likewise, both linearly
// over t in [0, 1] at their start orientations. The answer is the first t
// at which their distance is <= target = target_distance + linear_slop.
//
// Algorithm: relative to A, B moves by u = translation_b - translation_a, so
// the pair is within the target at t exactly when t u lies in
// K (+) ball(r_a + r_b + target), K = core_A - core_B the cores' Minkowski
// difference at t = 0 (in A's core frame, relative_pose of minkowski.hpp).
// That is a ray cast from the origin along u against K: the GJK ray cast of
// gjk_raycast.hpp, which only ever moves t onto supporting planes of the
// grown K, so t is never after the first contact (beyond rounding). It ends
// when the ray's point is within the tolerance of the grown K: the distance
// at t is then in [target, target + tolerance].
//
// Pairs within the target at t = 0 answer t = 0, initially_overlapping, with
// penetration()'s signed distance, normal and witnesses. A ray cast that
// stalls (or hits the cap) before its first clip has certified nothing at
// t = 0: penetration() settles the start (within the target, or apart with
// a separating direction that starts one more ray cast).
#pragma once

#include <Eigen/Core>
#include <hedra/collision/cast_result.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/shapes.hpp>

namespace hedra::collision {

struct ShapeCastSettings {
  // Contact when the distance is <= target_distance + linear_slop (both >= 0;
  // default: touching).
  double target_distance = 0.0;
  double linear_slop = 0.0;
  // A hit's distance is within tolerance * size above the target (size: the
  // larger bounding radius of the two shapes), and never below the rounding
  // of the pair's coordinates. The larger body sets the scale: against a
  // body 1e6 times larger, a small one stops within 1e-4 of its own size
  // (lower this to resolve it finer, down to that rounding).
  double tolerance = 1e-10;
  // Ray-cast iterations (polytopes: a few; curved cores: tens).
  int max_iterations = 128;
};

// `cache` (optional): the pair's last separating axis and polyhedron support
// hints (A's core frame, as for distance()); one per pair and thread.
CastResult shape_cast(const Shape& a, const Pose& pose_a, const Eigen::Vector3d& translation_a, const Shape& b,
                      const Pose& pose_b, const Eigen::Vector3d& translation_b, GjkCache* cache = nullptr,
                      const ShapeCastSettings& settings = {});

}  // namespace hedra::collision
