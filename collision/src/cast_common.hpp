// Internal: what shape_cast() and time_of_impact() share: input checks, the
// answer for a pair that starts within the target (penetration()'s), and
// the hit's witnesses taken from A's core frame to the world.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <hedra/collision/cast_result.hpp>
#include <hedra/collision/detail/minkowski.hpp>
#include <hedra/collision/query.hpp>
#include <limits>

namespace hedra::collision::cast_detail {

inline bool finite_within(const Eigen::Vector3d& x) {
  return x.allFinite() && x.cwiseAbs().maxCoeff() <= max_coordinate;
}

inline bool target_valid(double target_distance, double linear_slop) {
  return target_distance >= 0.0 && std::isfinite(target_distance) && linear_slop >= 0.0 && std::isfinite(linear_slop) &&
         target_distance + linear_slop <= max_shape_size;
}

// A pair within the target at t = 0: penetration()'s signed answer `p`.
inline CastResult initially_overlapping(const PenetrationResult& p) {
  CastResult out;
  out.status = CastStatus::initially_overlapping;
  out.hit = out.initially_overlapping = true;
  out.fraction = 0.0;
  out.distance = p.distance;
  out.normal = p.normal;
  out.point_a = p.point_a;
  out.point_b = p.point_b;
  out.error_bound = p.error_bound;
  out.support_calls = p.support_calls;
  return out;
}

inline CastResult initially_overlapping(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b) {
  return initially_overlapping(penetration(a, pose_a, b, pose_b));
}

// A continuous query whose iteration stopped (a stall or the cap) before
// certifying anything at t = 0 (its "t = 0 is free" would be unfounded):
// penetration() settles the start, when its answer brackets the signed
// distance (ok, or best so far within error_bound: stalled, polytope_full).
// `within`: possibly within the target plus the tolerance (the answer is
// then p's, initially_overlapping); `apart`: certainly beyond it, t = 0 is
// free and p.normal (world, A toward B) is the direction to search from.
// Neither: no verdict.
struct Start {
  bool within = false;
  bool apart = false;
  PenetrationResult p;
};

inline Start settle_start(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, double target,
                          double tolerance) {
  Start start;
  start.p = penetration(a, pose_a, b, pose_b);
  const Status s = start.p.status;
  if (s != Status::ok && s != Status::stalled && s != Status::polytope_full) return start;
  const double lower = start.p.distance - start.p.error_bound;
  start.within = lower <= target + tolerance;
  start.apart = !start.within && start.p.normal.squaredNorm() > 0.0;
  return start;
}

// A hit: core witnesses in A's core frame at the hit (core_b - core_a along
// n, |core_b - core_a| = core_distance), A's pose there (rotation_a,
// translation_a) and the radii. Witnesses are made consistent with the
// normal (their midpoint moved apart along n, as query.cpp does) and go to
// the world.
inline void set_hit(CastResult& out, double fraction, double core_distance, const Eigen::Vector3d& n,
                    const Eigen::Vector3d& core_a, const Eigen::Vector3d& core_b, double radius_a, double radius_b,
                    double target, const Eigen::Matrix3d& rotation_a, const Eigen::Vector3d& translation_a,
                    const Eigen::Vector3d& offset_a) {
  const Eigen::Vector3d mid = 0.5 * (core_a + core_b);
  const Eigen::Vector3d local_a = mid - (0.5 * core_distance - radius_a) * n;
  const Eigen::Vector3d local_b = mid + (0.5 * core_distance - radius_b) * n;
  out.status = CastStatus::hit;
  out.hit = true;
  out.fraction = fraction;
  out.distance = core_distance - radius_a - radius_b;
  // The distance at `fraction` is certified >= target (no contact before).
  out.error_bound = std::max(out.distance - target, 0.0);
  out.normal = rotation_a * n;
  out.point_a = rotation_a * (offset_a + local_a) + translation_a;
  out.point_b = rotation_a * (offset_a + local_b) + translation_a;
}

}  // namespace hedra::collision::cast_detail
