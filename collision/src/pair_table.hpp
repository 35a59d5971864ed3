// Which algorithm a pair of shapes gets: one table for contact() and
// penetration(), one line an unordered pair of shape types (after Box2D's
// contact.c registry and Jolt's CollisionDispatch). Read at compile time by
// manifold.cpp's contact_typed and query.cpp's penetration_typed.
//
// A route written for one order of its shapes (polytope_curved: the polytope
// is A; sphere_box: the sphere is A) runs a pair given the other way round
// with the shapes swapped and its answer flipped, in one place each
// (contact_typed, penetration_typed). The other routes take either order
// as given (a flip would move their answers by rounding).
//
// Run-time choices inside a route stay with the route:
//   * box_box declines some pairs (box_box.hpp: rounded cores touching, the
//     exact-normal search asked for, ContactSettings::box_box_path = false),
//     which then take the polytopes route;
//   * polytopes: a polyhedron without a solid hull takes single_point; SAT
//     or the exact normal by ContactSettings::axis_search (manifold.hpp);
//   * polytope_curved: a box against a capsule whose segment misses the
//     box's core gets its first point in closed form (segment_box.hpp);
//   * sphere_box: only when the centre is inside the box's core, else gjk_epa;
//   * box_sat: only overlapping boxes whose depth SAT certifies, else gjk_epa;
//   * penetration(): a point or segment hull runs as a sphere or a capsule
//     (query.cpp), then by this table.
#pragma once

#include <cstddef>
#include <hedra/collision/shapes.hpp>
#include <type_traits>
#include <variant>

namespace hedra::collision::detail {

enum class ContactRoute {
  box_box,          // box_box.cpp: SAT from the relative rotation, the box clipping
  polytopes,        // the polytope path: SAT or the exact normal, face or edge contact
  polytope_curved,  // a polytope (A) against a capsule, cylinder or cone: segment, cap or one point
  single_point,     // penetration()'s point
};

enum class PenetrationRoute {
  gjk_epa,     // GJK, then EPA or the exact revolution paths (query.cpp's PenetrationSteps)
  sphere_box,  // a sphere (A) whose centre is inside a box's core: closed_form.hpp
  box_sat,     // two overlapping boxes: SAT's 15 axes, certified (sat_depth.hpp)
};

// A shape type's index in Shape.
template <class S, std::size_t I = 0>
constexpr std::size_t shape_index() {
  if constexpr (std::is_same_v<std::variant_alternative_t<I, Shape>, S>)
    return I;
  else
    return shape_index<S, I + 1>();
}

struct PairLine {
  std::size_t a, b;  // shape indices, in the order the routes are written for
  ContactRoute contact;
  PenetrationRoute penetration;
};

inline constexpr std::size_t kSphere = shape_index<Sphere>(), kBox = shape_index<Box>(),
                             kCapsule = shape_index<Capsule>(), kCylinder = shape_index<Cylinder>(),
                             kCone = shape_index<Cone>(), kPolyhedron = shape_index<Polyhedron>();

// clang-format off
inline constexpr PairLine kPairTable[] = {
  // A            B             contact                          penetration
  {kSphere,     kSphere,      ContactRoute::single_point,     PenetrationRoute::gjk_epa},
  {kSphere,     kBox,         ContactRoute::single_point,     PenetrationRoute::sphere_box},
  {kSphere,     kCapsule,     ContactRoute::single_point,     PenetrationRoute::gjk_epa},
  {kSphere,     kCylinder,    ContactRoute::single_point,     PenetrationRoute::gjk_epa},
  {kSphere,     kCone,        ContactRoute::single_point,     PenetrationRoute::gjk_epa},
  {kSphere,     kPolyhedron,  ContactRoute::single_point,     PenetrationRoute::gjk_epa},
  {kBox,        kBox,         ContactRoute::box_box,          PenetrationRoute::box_sat},
  {kBox,        kCapsule,     ContactRoute::polytope_curved,  PenetrationRoute::gjk_epa},
  {kBox,        kCylinder,    ContactRoute::polytope_curved,  PenetrationRoute::gjk_epa},
  {kBox,        kCone,        ContactRoute::polytope_curved,  PenetrationRoute::gjk_epa},
  {kBox,        kPolyhedron,  ContactRoute::polytopes,        PenetrationRoute::gjk_epa},
  {kCapsule,    kCapsule,     ContactRoute::single_point,     PenetrationRoute::gjk_epa},
  {kCapsule,    kCylinder,    ContactRoute::single_point,     PenetrationRoute::gjk_epa},
  {kCapsule,    kCone,        ContactRoute::single_point,     PenetrationRoute::gjk_epa},
  {kPolyhedron, kCapsule,     ContactRoute::polytope_curved,  PenetrationRoute::gjk_epa},
  {kCylinder,   kCylinder,    ContactRoute::single_point,     PenetrationRoute::gjk_epa},
  {kCylinder,   kCone,        ContactRoute::single_point,     PenetrationRoute::gjk_epa},
  {kPolyhedron, kCylinder,    ContactRoute::polytope_curved,  PenetrationRoute::gjk_epa},
  {kCone,       kCone,        ContactRoute::single_point,     PenetrationRoute::gjk_epa},
  {kPolyhedron, kCone,        ContactRoute::polytope_curved,  PenetrationRoute::gjk_epa},
  {kPolyhedron, kPolyhedron,  ContactRoute::polytopes,        PenetrationRoute::gjk_epa},
};
// clang-format on

// The table's line for the pair (SA, SB), in either order.
template <class SA, class SB>
constexpr PairLine pair_line() {
  constexpr std::size_t a = shape_index<SA>(), b = shape_index<SB>();
  for (const PairLine& line : kPairTable)
    if ((line.a == a && line.b == b) || (line.a == b && line.b == a)) return line;
  return {a, b, ContactRoute::single_point, PenetrationRoute::gjk_epa};  // unreachable: the check below
}

// Whether a route is written for one order of its shapes.
constexpr bool ordered(ContactRoute r) { return r == ContactRoute::polytope_curved; }
constexpr bool ordered(PenetrationRoute r) { return r == PenetrationRoute::sphere_box; }

// The pair's line lists SA first (a pair of one type: always).
template <class SA, class SB>
inline constexpr bool listed_in_order = pair_line<SA, SB>().a == shape_index<SA>();

// (SA, SB) runs as (SB, SA), its answer flipped.
template <class SA, class SB>
inline constexpr bool contact_flipped = ordered(pair_line<SA, SB>().contact) && !listed_in_order<SA, SB>;
template <class SA, class SB>
inline constexpr bool penetration_flipped = ordered(pair_line<SA, SB>().penetration) && !listed_in_order<SA, SB>;

// Every unordered pair of shape types has exactly one line.
constexpr bool table_complete() {
  constexpr std::size_t n = std::variant_size_v<Shape>;
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a; b < n; ++b) {
      int lines = 0;
      for (const PairLine& line : kPairTable) lines += (line.a == a && line.b == b) || (line.a == b && line.b == a);
      if (lines != 1) return false;
    }
  return sizeof(kPairTable) / sizeof(PairLine) == n * (n + 1) / 2;
}
static_assert(table_complete(), "pair_table.hpp: one line for every unordered pair of shape types");

}  // namespace hedra::collision::detail
