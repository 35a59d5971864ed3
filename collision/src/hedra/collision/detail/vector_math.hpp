// The small vector helpers that supports, GJK and EPA share.
//
// dot3 and cross3 write a . b and a x b out per coordinate, in Eigen's order
// for one 3-vector (dot: (a0 b0 + a1 b1) + a2 b2), so the results are the
// same bits as Eigen's dot() and cross(); Eigen's SSE2 code for a lone
// 3-vector (a packet of two, shuffles, a scalar third) costs about twice the
// instructions in the support loops and in GJK's and EPA's inner loops.
// area_vector is a triangle's normal accurate in direction on slivers
// (derivation: docs/design.md, "Area vectors of slivers").
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace hedra::collision {

inline double dot3(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a.x() * b.x() + a.y() * b.y()) + a.z() * b.z();
}
inline Eigen::Vector3d cross3(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return {a.y() * b.z() - a.z() * b.y(), a.z() * b.x() - a.x() * b.z(), a.x() * b.y() - a.y() * b.x()};
}

// Twice the area vector of triangle p0 p1 p2 (normal, length twice the
// area): the cross product of the two edges that meet opposite the longest
// one, then its component along the longest edge removed. What is left of
// the rounding is a tilt about the longest edge, which moves the triangle's
// points by at most eps times its length.
inline Eigen::Vector3d area_vector(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2) {
  const Eigen::Vector3d e0 = p1 - p0, e1 = p2 - p1, e2 = p0 - p2;
  const double l0 = dot3(e0, e0), l1 = dot3(e1, e1), l2 = dot3(e2, e2);
  const bool longest0 = l0 >= l1 && l0 >= l2, longest1 = !longest0 && l1 >= l2;
  const Eigen::Vector3d& longest = longest0 ? e0 : (longest1 ? e1 : e2);
  const double ll = longest0 ? l0 : (longest1 ? l1 : l2);
  Eigen::Vector3d n = longest0 ? cross3(e1, e2) : (longest1 ? cross3(e2, e0) : cross3(e0, e1));
  // ll > 0 unless all three points coincide (n = 0 then); a non-finite ll
  // makes n non-finite, which every caller treats as degenerate.
  if (ll > 0.0) n -= (dot3(n, longest) / ll) * longest;
  return n;
}

// |n| = 1 within `tolerance` (what debug builds check of the normals the
// queries return).
inline bool is_unit(const Eigen::Vector3d& n, double tolerance = 1e-12) {
  return std::abs(dot3(n, n) - 1.0) <= tolerance;
}

// d / |d|, or zero when d is zero or not finite (a radius added along it
// then adds nothing, which keeps the answer finite).
inline Eigen::Vector3d safe_unit(const Eigen::Vector3d& d) {
  const double n = d.norm();
  if (!(n > 0.0) || !std::isfinite(n)) return Eigen::Vector3d::Zero();
  return d / n;
}

}  // namespace hedra::collision
