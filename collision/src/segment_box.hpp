// Closest points of a segment and a box, in closed form: the capsule-on-box
// contact's exact normal without GJK (Bullet's capsule-box pair runs GJK).
//
// In the box's frame (centred, half extents h), for a segment p0 + t d,
// t in [0, 1], that misses the box: the distance to a convex set is convex
// along the segment, so its minimum lies at an endpoint (the endpoint
// clamped to the box), or where the closest box point is on an edge (the
// closest points of the segment and that edge), or where the segment runs
// parallel to a face over its interior, and then also where that stretch
// begins or ends: at an endpoint or over an edge. So the minimum over the
// two endpoints and the twelve edges is the distance. A segment within tol
// of the box (the slab test on the box grown by tol) is left to the caller
// (overlapping or touching cores: the depth needs the full query).
// Closest points of two segments: Ericson, Real-Time Collision Detection,
// 5.1.9, with guarded divisions.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

namespace hedra::collision::detail {

// Closest points of segments p0 + s u and q0 + t v, s, t in [0, 1].
inline void closest_segment_points(const Eigen::Vector3d& p0, const Eigen::Vector3d& u, const Eigen::Vector3d& q0,
                                   const Eigen::Vector3d& v, Eigen::Vector3d& on_p, Eigen::Vector3d& on_q) {
  const Eigen::Vector3d r = p0 - q0;
  const double a = u.squaredNorm(), e = v.squaredNorm(), f = v.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= 0.0 && e <= 0.0) {
  } else if (a <= 0.0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = u.dot(r);
    if (e <= 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = u.dot(v), denom = a * e - b * b;
      s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  on_p = p0 + s * u;
  on_q = q0 + t * v;
}

// True when the segment p0 + t d, t in [0, 1], meets the box of half
// extents h grown by tol (slab test).
inline bool segment_meets_box(const Eigen::Vector3d& p0, const Eigen::Vector3d& d, const Eigen::Vector3d& h,
                              double tol) {
  double lo = 0.0, hi = 1.0;
  for (int k = 0; k < 3; ++k) {
    const double half = h[k] + tol;
    if (d[k] == 0.0) {
      if (std::abs(p0[k]) > half) return false;
      continue;
    }
    double t1 = (-half - p0[k]) / d[k], t2 = (half - p0[k]) / d[k];
    if (t1 > t2) std::swap(t1, t2);
    lo = std::max(lo, t1);
    hi = std::min(hi, t2);
    if (!(lo <= hi)) return false;
  }
  return true;
}

struct SegmentBoxClosest {
  double distance = std::numeric_limits<double>::infinity();
  Eigen::Vector3d on_segment = Eigen::Vector3d::Zero(), on_box = Eigen::Vector3d::Zero();
};

// The closest points (box frame), or false when the segment comes within
// tol of the box.
inline bool segment_box_closest(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& h,
                                double tol, SegmentBoxClosest& out) {
  const Eigen::Vector3d d = p1 - p0;
  if (!(tol >= 0.0) || segment_meets_box(p0, d, h, tol)) return false;
  out = SegmentBoxClosest{};
  const auto consider = [&](const Eigen::Vector3d& on_segment, const Eigen::Vector3d& on_box) {
    const double dist = (on_segment - on_box).norm();
    if (dist < out.distance) out = {dist, on_segment, on_box};
  };
  consider(p0, p0.cwiseMax(-h).cwiseMin(h));
  consider(p1, p1.cwiseMax(-h).cwiseMin(h));
  for (int k = 0; k < 3; ++k) {  // edges along axis k
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    Eigen::Vector3d along = Eigen::Vector3d::Zero();
    along[k] = 2.0 * h[k];
    for (int corner = 0; corner < 4; ++corner) {
      Eigen::Vector3d start;
      start[k] = -h[k];
      start[i] = corner & 1 ? h[i] : -h[i];
      start[j] = corner & 2 ? h[j] : -h[j];
      Eigen::Vector3d on_segment, on_box;
      closest_segment_points(p0, d, start, along, on_segment, on_box);
      consider(on_segment, on_box);
    }
  }
  return out.distance > tol;
}

}  // namespace hedra::collision::detail
