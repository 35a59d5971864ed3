// Internal: what shape_cast() and time_of_impact() share: input checks, the
// answer for a pair that starts within the target (penetration()'s), and
// the hit's witnesses taken from A's core frame to the world.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <hedra/collision/cast_result.hpp>
#include <hedra/collision/gjk.hpp>
#include <hedra/collision/minkowski.hpp>
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

// Polyhedron support hints travel through the caller's GjkCache.
template <class Core>
void load_hint(Core&, hull::Index) {}
inline void load_hint(PolyhedronCore& core, hull::Index hint) { core.hint = hint; }
template <class Core>
hull::Index hint_of(const Core&) {
  return 0;
}
inline hull::Index hint_of(const PolyhedronCore& core) { return core.hint; }

// `v`: point_a - point_b in A's core frame (GjkCache's convention).
template <class CoreA, class CoreB>
void store_cache(GjkCache* cache, const Eigen::Vector3d& v, const CoreA& a, const CoreB& b) {
  if (!cache) return;
  if (v.allFinite() && v.squaredNorm() > 0.0) {
    cache->axis = v;
    cache->valid = true;
  }
  cache->hint_a = hint_of(a);
  cache->hint_b = hint_of(b);
}

// A pair within the target at t = 0: penetration()'s signed answer.
inline CastResult initially_overlapping(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b) {
  const PenetrationResult p = penetration(a, pose_a, b, pose_b);
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
