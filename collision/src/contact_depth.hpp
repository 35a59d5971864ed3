// The depth a face or edge contact reports: the overlap along its axis.
//
// For a unit axis n (A toward B) the overlap of the two shapes along n is
// h_A(n) + h_B(-n) (support values, margins included); SAT measures a
// face's separation from exact supports, so an axis's separation s is
// -(h_A(n) + h_B(-n)). A point whose witnesses lie on both surfaces on one
// line along n is at most that deep, and exactly that deep only where the
// two support features (the reference face, the incident shape's deepest
// vertex, edge or face) overlap seen along n. When the reference face's
// side planes clip away the incident shape's deepest vertex they do not:
// no contact point can be as deep as the axis says, and the manifold must
// stand on another normal (the exact one, penetration()'s, whose support
// features always overlap: its witnesses are as deep as its overlap).
// Invariant kept by the callers (manifold.cpp, box_box.cpp): a face or edge
// manifold's deepest point is the overlap along its normal to rounding (the
// touching band), but for warm queries holding last frame's points
// (ContactSettings::hold, at most that much shallower).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <hedra/collision/shapes.hpp>
#include <limits>

namespace hedra::collision::detail {

// Whether the deepest kept point (`deepest`: its separation, > the axis's
// when shallower) falls short of the axis's separation `axis` by more than
// rounding (`band`), or of the pair's exact separation (`exact_limit`, with
// its tolerance; +infinity when not known); `held`: how much shallower a
// warm query's held points may be.
inline bool deepest_short_of_axis(double deepest, double axis, double exact_limit, double band, double held) {
  return deepest > std::min(axis + band, exact_limit) + held;
}

// The error bound of an answer of distance d whose exact signed distance is
// known to lie within `radius` of `center` (a bracket's midpoint and half
// width): |d - center| + radius, or the answer's own bound if smaller (both
// hold). ContactResult::error_bound starts at +infinity (nothing certified).
inline double bound_within(double d, double current, double center, double radius) {
  return std::min(current, std::abs(d - center) + radius);
}

// A size at least the shape's bounding radius, without a square root (for
// the rounding allowance below: a few instructions on the hot path).
inline double rough_size(const Sphere& s) { return s.radius + s.margin; }
inline double rough_size(const Box& s) { return s.half_extents.cwiseAbs().sum() + s.margin; }
inline double rough_size(const Capsule& s) { return s.radius + s.half_length + s.margin; }
inline double rough_size(const Cylinder& s) { return s.radius + s.half_length + s.margin; }
inline double rough_size(const Cone& s) { return s.radius + s.half_length + s.margin; }
inline double rough_size(const Polyhedron& s) { return s.hull->bounding_radius() + s.margin; }

// Rounding of the contact geometry: a few hundred ulps of the pair's size
// and of the distance between the two poses (the relative pose; its 1-norm).
inline double contact_rounding(double size, const Eigen::Vector3d& between_poses) {
  return 256.0 * std::numeric_limits<double>::epsilon() * (size + between_poses.cwiseAbs().sum());
}

}  // namespace hedra::collision::detail
