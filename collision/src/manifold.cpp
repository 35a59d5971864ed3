// contact(): the inputs checked once, at the edge; the pair's route by its
// shape types (pair_table.hpp: box_box.cpp, the polytope path of
// contact_polytopes.cpp, the curved shapes of contact_curved.cpp, or
// penetration()'s point), a pair given in the other order than its route is
// written for swapped and flipped here; what every answer promises
// (manifold.hpp) asserted on the way out. docs/contacts.md describes the
// paths.
#include <algorithm>
#include <cmath>
#include <hedra/collision/manifold.hpp>
#include <hedra/hull/assert.hpp>
#include <limits>
#include <type_traits>

#include "box_box.hpp"
#include "contact_common.hpp"
#include "contact_depth.hpp"
#include "pair_table.hpp"
#include "query_detail.hpp"

namespace hedra::collision {

const char* to_string(ContactPath path) {
  switch (path) {
    case ContactPath::none:
      return "none";
    case ContactPath::separated:
      return "separated";
    case ContactPath::face_a:
      return "face_a";
    case ContactPath::face_b:
      return "face_b";
    case ContactPath::edge:
      return "edge";
    case ContactPath::segment:
      return "segment";
    case ContactPath::cap:
      return "cap";
    case ContactPath::single_point:
      return "single_point";
  }
  return "unknown";
}

namespace {

using namespace detail::manifold;

// penetration() on a polytope pair's typed shapes (PolytopePair::penetrate).
template <class SA, class SB>
PenetrationResult penetrate_typed(const PolytopePair& pp, ContactCache* cache, const ContactSettings& settings) {
  return detail::penetration_unchecked(*static_cast<const SA*>(pp.shape_a), *pp.pose_a,
                                       *static_cast<const SB*>(pp.shape_b), *pp.pose_b, cache ? &cache->gjk : nullptr,
                                       settings.penetration);
}

template <class SA, class SB>
ContactResult polytope_contact(const SA& a, const Pose& pose_a, const SB& b, const Pose& pose_b, ContactCache* cache,
                               const ContactSettings& settings) {
  BoxPolytopeStorage storage_a, storage_b;
  PolytopePair pp;
  polytope_view(a, storage_a, pp.pa);
  polytope_view(b, storage_b, pp.pb);
  pp.rel = relative_pose(pose_a, core_offset(a), pose_b, core_offset(b));
  pp.placed_b = {pp.rel.rotation, pp.rel.translation};
  pp.ra = core_radius(a);
  pp.rb = core_radius(b);
  pp.scale = scale_of(pp.pa, pp.pb) + std::max(pp.ra, pp.rb);
  pp.keep = keep_below(settings, pp.scale);
  pp.band = settings.penetration.touching_band * pp.scale;
  pp.last = cache;
  pp.hold = settings.hold * pp.scale;
  pp.core_contact = pp.keep + pp.ra + pp.rb;
  pp.shape_scale = std::max(bounding_radius(a), bounding_radius(b));
  pp.shape_a = &a;
  pp.shape_b = &b;
  pp.pose_a = &pose_a;
  pp.pose_b = &pose_b;
  pp.penetrate = &penetrate_typed<SA, SB>;
  const WorldFrame world{pose_a, core_offset(a)};
  return polytope_manifold(pp, world, cache, settings);
}

// The pair's route (pair_table.hpp); a pair given in the other order than
// its route is written for runs swapped, its answer flipped here.
template <class SA, class SB>
ContactResult contact_typed(const SA& a, const Pose& pose_a, const SB& b, const Pose& pose_b, ContactCache* cache,
                            const ContactSettings& settings) {
  if constexpr (detail::contact_flipped<SA, SB>) {
    ContactResult r = contact_typed(b, pose_b, a, pose_a, cache, settings);
    flip(r);
    return r;
  } else {
    constexpr detail::ContactRoute route = detail::pair_line<SA, SB>().contact;
    if constexpr (route == detail::ContactRoute::box_box) {
      ContactResult r;  // box_box.cpp; what it hands back, the polytope path answers
      if (detail::box_box_contact(a, pose_a, b, pose_b, cache, settings, r)) return r;
    } else if (cache) {
      cache->box.valid = false;  // the box memory is for box pairs only
    }
    if constexpr (route == detail::ContactRoute::box_box || route == detail::ContactRoute::polytopes) {
      if (!solid(a) || !solid(b)) return single_point(a, pose_a, b, pose_b, cache, settings);
      return polytope_contact(a, pose_a, b, pose_b, cache, settings);
    } else if constexpr (route == detail::ContactRoute::polytope_curved) {
      return curved_contact(a, pose_a, b, pose_b, cache, settings);
    } else {
      static_assert(route == detail::ContactRoute::single_point);
      return single_point(a, pose_a, b, pose_b, cache, settings);
    }
  }
}

// What manifold.hpp promises of every answer, asserted where HEDRA_ASSERT
// is on: at most four points; with points, a unit normal (to the rotation
// tolerance the poses are held to), the witnesses apart by the distance
// along it (to 1e-5 of the size, emit()'s bound, plus the world
// coordinates' rounding) and points[0] the point they belong to.
#if HEDRA_ASSERTS_ENABLED
void assert_contract(const ContactResult& r, const Shape& a, const Shape& b) {
  HEDRA_ASSERT(r.count >= 0 && r.count <= kMaxContactPoints);
  if (r.count == 0) return;
  const double size = std::max(bounding_radius(a), bounding_radius(b));
  const double reach = std::max({r.point_a.cwiseAbs().maxCoeff(), r.point_b.cwiseAbs().maxCoeff(), size});
  const double rounding = 64.0 * std::numeric_limits<double>::epsilon() * reach;
  HEDRA_ASSERT(std::abs(r.normal.squaredNorm() - 1.0) <= 8.0 * rotation_tolerance);
  HEDRA_ASSERT((r.point_b - r.point_a - r.distance * r.normal).norm() <= 1e-5 * size + rounding);
  HEDRA_ASSERT(r.points[0].depth == -r.distance);
  for (int k = 0; k < r.count; ++k) HEDRA_ASSERT(std::isfinite(r.points[k].depth) && r.points[k].point.allFinite());
}
#endif

ContactResult invalid_input() {
  ContactResult out;
  out.status = Status::invalid_input;
  return out;
}

}  // namespace

ContactResult contact(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, ContactCache* cache,
                      const ContactSettings& settings) {
  // valid(), not only finite(): translations beyond max_coordinate are invalid in
  // every query.
  // is_valid(): validate()'s predicate without building its message.
  if (!pose_a.valid() || !pose_b.valid() || !is_valid(a) || !is_valid(b) || !pair_in_range(a, pose_a, b, pose_b) ||
      !std::isfinite(settings.contact_distance))
    return invalid_input();
  const auto typed = [&](const auto& sa, const auto& sb) {
    ContactResult r = contact_typed(sa, pose_a, sb, pose_b, cache, settings);
    if (r.status == Status::invalid_input || r.status == Status::degenerate)
      r.error_bound = std::numeric_limits<double>::infinity();
    else if (std::isfinite(r.error_bound))
      r.error_bound += detail::contact_rounding(detail::rough_size(sa) + detail::rough_size(sb),
                                                pose_b.translation - pose_a.translation);
    HEDRA_ASSERT(r.error_bound >= 0.0);  // manifold.hpp: a bound, never NaN
    return r;
  };
#if HEDRA_ASSERTS_ENABLED
  ContactResult r = std::visit(typed, a, b);
  assert_contract(r, a, b);
  return r;
#else
  return std::visit(typed, a, b);  // in the caller's slot (GCC copied a named result: 56 instructions)
#endif
}

}  // namespace hedra::collision
