// The halfspace: every simulator's floor (MuJoCo's plane, Bullet's
// btStaticPlaneShape), and its closed-form queries against every Shape.
//
//   Halfspace{normal, margin}: in its pose's frame the solid
//   { x : normal . x <= margin }; `normal` is a unit vector (validate() accepts
//   |normal| within 1e-6 of 1, the queries use normal / |normal|), `margin`
//   >= 0 raises the surface by that much, as a margin rounds the other shapes.
//
// Why it is not an alternative of Shape: it is unbounded (no support in any
// direction with a positive normal component, no bounding radius, no world
// box for a broadphase), so GJK, EPA, SAT and the casts, which visit Shape
// pairs, would each need a case that answers nothing like their other cases.
// Against a halfspace every query is closed form instead, from the other
// shape's support in -n and its features (docs/contacts.md, "Halfspaces").
//
// With n the world normal, c the plane's offset along it and B's rounding r
// (sphere, capsule: radius + margin; the others: margin), B's core point p
// is g(p) = n . p - c - r above the surface (g < 0: below). The signed
// distance is min over B's core of g: the gap of B's support point in -n.
// contact() returns the features of B with g <= contact_distance (plus the
// touching band, 1e-9 of B's size), reduced to four like manifold.hpp's face
// contacts (the deepest, the farthest from it in the plane, the largest
// positive and negative triangle areas with those two; ties to the first):
//   box        its corners                        FeatureKind::face_vertex, incident = corner (bit i: +axis i)
//   polyhedron its vertices (a scan of all)       face_vertex, incident = vertex index
//   capsule    the segment's ends                 segment, incident = 0 (-z end), 1 (+z end)
//   cylinder   per cap: the rim on +-x, +-y and   cap, clip = 0 (-z cap) or 1 (+z cap), incident = 0..3 rim
//              the deepest rim point                +x, -x, +y, -y, 4 deepest rim point
//   cone       the apex, the base rim as above    cap, clip = 1 incident = 5 (apex); clip = 0 as the cylinder's
//   sphere     its centre                         single, incident = 0
// (reference = 0, the halfspace's one face; reference_on_b false; points
// that coincide are kept once). The deepest point is B's exact support, so
// the deepest depth is the exact depth; every point's depth is the exact gap
// of the two surfaces on its line along n. The normal points from the
// halfspace toward B (A is the halfspace in every query). With a cache and
// ContactSettings::hold > 0 the last four are kept while they hold, as in
// manifold.hpp.
//
// A point whose line along -n runs on inside B (a rounded shape's, or a
// corner under a thin plate's top) gets the gap to where the line leaves B:
// closed forms, or one ray cast for rounded shapes and cones.
//
// Status: invalid_input for an invalid halfspace or shape, a pose that is
// not Pose::valid(), a pair out of range (query.hpp; the extent is B's size
// or its distance to the plane) or a non-finite contact distance; otherwise
// ok. No allocation; the polyhedron's scan visits each vertex a few times.
#pragma once

#include <Eigen/Core>
#include <hedra/collision/manifold.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/raycast.hpp>
#include <hedra/collision/shapes.hpp>

namespace hedra::collision {

struct Halfspace {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // outward, local frame
  double margin = 0.0;                                // the surface at normal . x = margin
};

// ok, or non_finite (normal or margin), out_of_range (|normal| not 1 within
// 1e-6, or margin beyond max_shape_size), negative_margin.
ShapeValidation validate(const Halfspace& h);
bool is_valid(const Halfspace& h);

IntersectResult intersect(const Halfspace& a, const Pose& pose_a, const Shape& b, const Pose& pose_b);
DistanceResult distance(const Halfspace& a, const Pose& pose_a, const Shape& b, const Pose& pose_b);
PenetrationResult penetration(const Halfspace& a, const Pose& pose_a, const Shape& b, const Pose& pose_b);
ContactResult contact(const Halfspace& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                      ContactCache* cache = nullptr, const ContactSettings& settings = {});

// A ray against the halfspace: origin + t direction, t in [0, max_fraction].
// Starting inside (or within 16 eps of the origin's distance to the plane's
// point, the rounding of the ray's coordinates): initially_overlapping at 0,
// no normal; otherwise a hit where the ray crosses the surface going down,
// with the outward normal. settings.tolerance is not used: there is no size.
RaycastResult raycast(const Halfspace& h, const Pose& pose, const Eigen::Vector3d& origin,
                      const Eigen::Vector3d& direction, double max_fraction = 1.0,
                      const RaycastSettings& settings = {});

}  // namespace hedra::collision
