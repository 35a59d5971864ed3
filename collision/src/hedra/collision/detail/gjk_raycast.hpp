// GJK ray cast (van den Bergen, "Ray casting against general convex objects
// with application to continuous collision detection", 2004) against
// K (+) ball(radius), K = A - B the Minkowski difference of two support types
// in one frame (a shape against a fixed point for a ray; two cores for a
// shape cast, whose relative motion is the ray).
//
// The ray is x(lambda) = lambda u from the frame's origin. The loop keeps a
// simplex of points p_i of K and v = x - (closest point of conv{p_i} to x),
// so |v| >= dist(x, K). Each iteration takes p = s_K(v); when x lies beyond
// the supporting plane v . y = v . p grown by the radius, the whole set lies
// behind that plane, the ray cannot meet it before the plane, and lambda
// jumps to the plane (clipping); a ray parallel to or leaving the plane
// misses. Then p joins the simplex and the signed-volumes sub-algorithm of
// gjk.hpp gives the new v from the points x - p_i.
//
// Invariant: lambda only moves to supporting planes of K (+) ball, so no
// contact happens before it (exact arithmetic; rounding moves a plane by a
// few eps of the coordinates, which the tolerance covers). Ends:
//   |v| <= radius + tolerance: x is within the tolerance of the set: a hit
//     at lambda (lambda = 0 without a clip: it started inside);
//   lambda > max_lambda or a leaving ray: separated;
//   p already in the simplex with no clip, or |v| failing to decrease
//     without a clip: stalled (lambda is still safe);
//   the cap: max_iterations (lambda safe); a non-finite point: degenerate.
// "Safe" says nothing of lambda = 0 itself before the first clip (`clipped`
// false): v is only an upper bound there, and on a thin set (a cone 1e9
// times wider than thick) its direction's rounding, eps |p| / |v|, can keep
// the far side's support out of the simplex, so a start inside stalls. The
// caller settles such a start with a certified query.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <hedra/collision/cast_result.hpp>
#include <hedra/collision/detail/gjk.hpp>
#include <hedra/hull/assert.hpp>
#include <limits>

namespace hedra::collision {

// A support type that is one point (a ray's origin).
struct FixedPoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d support(const Eigen::Vector3d&) const { return point; }
};

struct GjkRaycastResult {
  CastStatus status =
      CastStatus::separated;  // hit, initially_overlapping, separated, max_iterations, stalled, degenerate
  double lambda = 0.0;        // safe: no contact before it
  // v = x(lambda) - (point_a - point_b), |v| >= dist(x, K): from K toward the ray.
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  // Unit outward normal at the hit: v / |v| when the radius dominates the
  // tolerance, else the last clipping plane's normal; zero before any clip
  // on a radius too small to give a direction.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  // the simplex's closest point, split into A's
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  // and B's parts (B at lambda = 0)
  double gap = 0.0;                                   // |v| - radius: the distance at lambda is at most this
  // lambda moved onto a supporting plane at least once: the point at lambda
  // is certified outside the set (within rounding). False on a stall or the
  // cap before any clip: nothing is known of the start.
  bool clipped = false;
  int iterations = 0;
  int support_calls = 0;
};

// A stall or the cap before the first clip: no verdict, not even that
// lambda = 0 is free.
inline bool start_unsettled(const GjkRaycastResult& r) {
  return (r.status == CastStatus::stalled || r.status == CastStatus::max_iterations) && !r.clipped;
}

namespace raycast_detail {

struct RaySimplex {
  int size = 0;
  std::array<Eigen::Vector3d, 4> p;  // points of K
  std::array<Eigen::Vector3d, 4> a;  // their A and B parts, p = a - b
  std::array<Eigen::Vector3d, 4> b;
  std::array<double, 4> lambda{};
};

// Rewrites the simplex as the sub-simplex `sub` chosen among its first
// `count` points.
inline void keep(RaySimplex& s, const gjk_detail::Sub& sub) {
  RaySimplex t;
  for (int i = 0; i < sub.size; ++i) {
    t.p[i] = s.p[sub.index[i]];
    t.a[i] = s.a[sub.index[i]];
    t.b[i] = s.b[sub.index[i]];
    t.lambda[i] = sub.lambda[i];
  }
  t.size = sub.size;
  s = t;
}

inline void witnesses(const RaySimplex& s, GjkRaycastResult& r) {
  r.point_a.setZero();
  r.point_b.setZero();
  for (int i = 0; i < s.size; ++i) {
    r.point_a += s.lambda[i] * s.a[i];
    r.point_b += s.lambda[i] * s.b[i];
  }
}

}  // namespace raycast_detail

// `initial_axis`: a guess of v (from K toward the ray), e.g. -u or a cached
// axis. `tolerance`: absolute, in the frame's length unit (the caller scales
// it to the pair's size and the coordinates' rounding).
template <class A, class B>
GjkRaycastResult gjk_raycast(const A& a, const B& b, double radius, const Eigen::Vector3d& u, double max_lambda,
                             const Eigen::Vector3d& initial_axis, double tolerance, int max_iterations) {
  using raycast_detail::RaySimplex;
  GjkRaycastResult r;
  RaySimplex s;
  Eigen::Vector3d axis = initial_axis;
  if (!axis.allFinite() || !(axis.squaredNorm() > 0.0)) axis = Eigen::Vector3d::UnitX();
  // Any point of K starts v (the simplex stays empty until the first step).
  const Eigen::Vector3d start_a = a.support(axis), start_b = b.support(-axis);
  const Eigen::Vector3d start = start_a - start_b;
  r.support_calls = 1;
  if (!start.allFinite()) {
    r.status = CastStatus::degenerate;
    return r;
  }
  double lambda = 0.0;
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  Eigen::Vector3d v = -start;
  Eigen::Vector3d clip_normal = Eigen::Vector3d::Zero();
  bool clipped_ever = false;
  for (;;) {
    const double vv = v.squaredNorm();
    const double vn = gjk_detail::length_of(v, vv);
    if (vn <= radius + tolerance) {
      r.status = clipped_ever ? CastStatus::hit : CastStatus::initially_overlapping;
      break;
    }
    if (r.iterations >= max_iterations) {
      r.status = CastStatus::max_iterations;
      break;
    }
    ++r.iterations;
    const Eigen::Vector3d pa = a.support(v), pb = b.support(-v);
    ++r.support_calls;
    const Eigen::Vector3d p = pa - pb;
    if (!p.allFinite()) {
      r.status = CastStatus::degenerate;
      break;
    }
    // Clip against the supporting plane grown by the radius.
    const double beyond = v.dot(x - p) - radius * vn;
    bool clipped = false;
    if (beyond > 0.0) {
      const double vu = v.dot(u);
      if (!(vu < 0.0)) {
        r.status = CastStatus::separated;  // the plane separates the whole ray
        break;
      }
      const double next = lambda - beyond / vu;
      HEDRA_ASSERT(next >= lambda);
      if (!(next <= max_lambda)) {
        r.status = CastStatus::separated;
        break;
      }
      lambda = next;
      x = lambda * u;
      clip_normal = v / vn;
      clipped = clipped_ever = true;
    }
    bool duplicate = false;
    for (int i = 0; i < s.size; ++i) duplicate = duplicate || s.p[i] == p;
    if (duplicate && !clipped) {
      // Why: the sub-algorithm would return the same v; what is left above
      // the tolerance is rounding in v or p.
      r.status = CastStatus::stalled;
      break;
    }
    int count = s.size;
    if (!duplicate) {
      s.p[count] = p;
      s.a[count] = pa;
      s.b[count] = pb;
      ++count;
    }
    std::array<Eigen::Vector3d, 4> w;
    for (int i = 0; i < count; ++i) w[i] = x - s.p[i];
    gjk_detail::Sub sub;
    const bool inside = gjk_detail::signed_volumes(w, count, sub);
    const double vv_next = inside ? 0.0 : sub.point.squaredNorm();
    // (The first v comes from outside the simplex: nothing to compare.)
    if (!clipped && s.size > 0 && !(vv_next < vv)) {
      r.status = CastStatus::stalled;  // no decrease at a fixed x: rounding (or NaN)
      break;
    }
    s.size = count;
    raycast_detail::keep(s, sub);
    v = inside ? Eigen::Vector3d::Zero() : sub.point;
  }
  r.lambda = lambda;
  r.clipped = clipped_ever;
  r.v = v;
  raycast_detail::witnesses(s, r);
  if (s.size == 0) {  // no step taken: the starting point
    r.point_a = start_a;
    r.point_b = start_b;
  }
  const double vn = v.norm();
  r.gap = vn - radius;
  // v's direction is good to about tolerance / |v|: trust it when |v| is
  // well above the tolerance (a rounded set at the hit), else the plane.
  r.normal = vn > 1e3 * tolerance ? Eigen::Vector3d(v / vn) : clip_normal;
  return r;
}

}  // namespace hedra::collision
