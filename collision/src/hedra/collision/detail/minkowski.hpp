// The small wrappers that compose support mappings without virtual
// calls: each wrapper is itself a support type (`support(d) const`).
//
//   Transformed<S>          s'(d) = R s(R^T d) + t: a core placed by a pose;
//   Rounded<S>              s'(d) = s(d) + r d/|d|: a core plus a ball
//                           (used where the full shape is needed, e.g. EPA);
//   MinkowskiDifference<A,B> s'(d) = a(d) - b(-d): the configuration-space
//                           obstacle whose distance to the origin is the
//                           distance between A and B.
//
// Frames. The query layer never transforms vertex arrays and never works in
// world coordinates: B is expressed in A's core frame once per query,
//   R = R_a^T R_b,
//   t = R_a^T ((t_b - t_a) + (R_b o_b - R_a o_a)),
// where o_a, o_b are the cores' offsets in their shapes' frames (a
// polyhedron's centroid, zero otherwise). The large world translations are
// subtracted first, exactly when they are close, and only then combined with
// the small offset terms, so shapes at 1e6 lose nothing of their own size.
// Results go back to world coordinates at the very end.
//
// Rounding (spheres, capsules, margins) is never pushed through GJK: the
// core's answer is offset by the radius along the normal analytically.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <hedra/collision/detail/support.hpp>
#include <hedra/collision/pose.hpp>
#include <hedra/collision/settings.hpp>
#include <limits>

namespace hedra::collision {

template <class S>
struct Transformed {
  const S& shape;
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  // R s(R^T d) + t written out per coordinate, each sum in the order of
  // Eigen 3.4's SSE2 code for these two 3x3 products (the same bits: the
  // rows of R^T d and the first two of R x as (r0 x0 + r1 x1) + r2 x2, the
  // third row, its scalar tail, as (r1 x1 + r2 x2) + r0 x0), at fewer
  // instructions than its packets and shuffles for a lone 3-vector.
  Eigen::Vector3d support(const Eigen::Vector3d& d) const {
    const Eigen::Matrix3d& r = rotation;
    const Eigen::Vector3d local{(r(0, 0) * d.x() + r(1, 0) * d.y()) + r(2, 0) * d.z(),
                                (r(0, 1) * d.x() + r(1, 1) * d.y()) + r(2, 1) * d.z(),
                                (r(0, 2) * d.x() + r(1, 2) * d.y()) + r(2, 2) * d.z()};
    const Eigen::Vector3d x = shape.support(local);
    return {((r(0, 0) * x.x() + r(0, 1) * x.y()) + r(0, 2) * x.z()) + translation.x(),
            ((r(1, 0) * x.x() + r(1, 1) * x.y()) + r(1, 2) * x.z()) + translation.y(),
            ((r(2, 1) * x.y() + r(2, 2) * x.z()) + r(2, 0) * x.x()) + translation.z()};
  }
};

template <class S>
struct Rounded {
  const S& core;
  double radius = 0.0;
  Eigen::Vector3d support(const Eigen::Vector3d& d) const { return core.support(d) + radius * safe_unit(d); }
};

template <class A, class B>
struct MinkowskiDifference {
  const A& a;
  const B& b;
  Eigen::Vector3d support(const Eigen::Vector3d& d) const { return a.support(d) - b.support(-d); }
};

// B's core pose in A's core frame (see the top of this file).
struct RelativePose {
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
};

inline RelativePose relative_pose(const Pose& pose_a, const Eigen::Vector3d& offset_a, const Pose& pose_b,
                                  const Eigen::Vector3d& offset_b) {
  const Eigen::Vector3d between =
      (pose_b.translation - pose_a.translation) + (pose_b.rotation * offset_b - pose_a.rotation * offset_a);
  return {pose_a.rotation.transpose() * pose_b.rotation, pose_a.rotation.transpose() * between};
}

// A shape split into its core (what GJK runs on), the radius added
// analytically, and the core's offset in the shape's frame.
inline PointCore core_of(const Sphere&) { return {}; }
inline BoxCore core_of(const Box& s) { return {s.half_extents}; }
inline SegmentCore core_of(const Capsule& s) { return {s.half_length}; }
inline CylinderCore core_of(const Cylinder& s) { return {s.radius, s.half_length}; }
inline ConeCore core_of(const Cone& s) { return {s.radius, s.half_length}; }
// No hint yet: the first climb starts from the hull's start vertices.
inline PolyhedronCore core_of(const Polyhedron& s) { return {s.hull.get(), hull::kInvalidIndex}; }

inline double core_radius(const Sphere& s) { return s.radius + s.margin; }
inline double core_radius(const Box& s) { return s.margin; }
inline double core_radius(const Capsule& s) { return s.radius + s.margin; }
inline double core_radius(const Cylinder& s) { return s.margin; }
inline double core_radius(const Cone& s) { return s.margin; }
inline double core_radius(const Polyhedron& s) { return s.margin; }

template <class S>
Eigen::Vector3d core_offset(const S&) {
  return Eigen::Vector3d::Zero();
}
inline Eigen::Vector3d core_offset(const Polyhedron& s) { return s.hull->offset(); }

// Warm starts through the caller's GjkCache: the last axis v (point_a -
// point_b in A's core frame) and the polyhedron cores' support hints (other
// cores have none).
template <class Core>
void load_hint(Core&, hull::Index) {}
inline void load_hint(PolyhedronCore& core, hull::Index hint) { core.hint = hint; }
template <class Core>
hull::Index hint_of(const Core&) {
  return 0;
}
inline hull::Index hint_of(const PolyhedronCore& core) { return core.hint; }

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

}  // namespace hedra::collision
