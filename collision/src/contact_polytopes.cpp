// Polytope pairs (boxes and solid hulls) in A's core frame: the candidate
// axes from SAT (sat.hpp) or from penetration()'s exact normal, the face bias
// (contact_choice.hpp), the face or edge contact built on the chosen axis;
// rounded or apart cores along their exact normal; the cached axis
// re-measured at the new poses and certified exact (face_certificate.hpp)
// before any search. docs/contacts.md describes the choices.
#include <algorithm>
#include <cmath>
#include <hedra/hull/assert.hpp>
#include <hedra/hull/mesh_edit.hpp>
#include <limits>

#include "contact_choice.hpp"
#include "contact_common.hpp"
#include "contact_depth.hpp"
#include "face_certificate.hpp"
#include "segment_box.hpp"

namespace hedra::collision::detail::manifold {

using detail::closest_segment_points;

namespace {

// The endpoints of edge ea of A and edge eb of B in A's core frame.
struct EdgePairEnds {
  Vec a0, a1, b0, b1;
};

EdgePairEnds edge_pair_ends(const PolytopePair& pp, Index ea, Index eb) {
  const hull::HalfEdgeMesh& ma = *pp.pa.mesh;
  const hull::HalfEdgeMesh& mb = *pp.pb.mesh;
  return {pp.pa.vertex(ma.origin(ea)), pp.pa.vertex(ma.destination(ea)), pp.placed_b.point(pp.pb.vertex(mb.origin(eb))),
          pp.placed_b.point(pp.pb.vertex(mb.destination(eb)))};
}

// The edge of `poly` at its support vertex in n (poly's frame) most nearly
// perpendicular to n: where an edge-edge contact along n lies. Named by the
// smaller of its half-edges (as SAT names edges).
Index edge_across(const SatPolytope& poly, const Vec& n) {
  const hull::HalfEdgeMesh& m = *poly.mesh;
  const Index v = poly.support(n);
  Index best = hull::kInvalidIndex;
  double best_slope = std::numeric_limits<double>::infinity();
  for (const Index e : m.vertex_outgoing(v)) {
    const Vec d = poly.vertex(m.destination(e)) - poly.vertex(v);
    const double slope = std::abs(n.dot(d)) / d.norm();
    if (slope < best_slope) {
      best_slope = slope;
      best = e;
    }
  }
  return best == hull::kInvalidIndex ? best : std::min(best, m.twin(best));
}

// Polytopes whose cores are apart (rounded ones whose margins overlap or lie
// within the contact distance; sharp ones within it whose SAT contact is not
// exact, see build_manifold): SAT's axes only bound the cores' distance,
// so the manifold is built around the exact normal n of the cores' closest
// features (penetration()'s, GJK on the cores). When n is within the face
// angle tolerance of a face normal of A or of B (closest features
// face-vertex, face-edge or face-face, or a face's edge or corner against a
// part of the other shape overhanging it: n tilted off the face), that face
// is the reference: the incident face is clipped by its side planes swept
// along n, and every point's depth is the exact gap of the rounded surfaces
// along n (core gap less both exits), so the deepest is penetration()'s
// (its witnesses added where n's own error clips them away). Otherwise the
// closest features are a vertex or an edge on each side and the contact is
// penetration()'s single point.

// The face for the exact normal n (A's frame, A -> B): A's within the face
// angle tolerance of n, else B's; kind none when neither.
SatAxis rounded_face_along(const PolytopePair& pp, const Vec& n, const ContactSettings& settings) {
  const double cos_tol = std::cos(settings.face_angle_tolerance);
  SatAxis axis;
  const Index fa = face_along(pp.pa, n, cos_tol);
  if (fa != hull::kInvalidIndex) {
    axis.kind = SatAxisKind::face_a;
    axis.feature_a = fa;
    axis.normal = pp.pa.plane(fa).normal;
    return axis;
  }
  const Index fb = face_along(pp.pb, pp.rel.rotation.transpose() * -n, cos_tol);
  if (fb != hull::kInvalidIndex) {
    axis.kind = SatAxisKind::face_b;
    axis.feature_b = fb;
    axis.normal = -(pp.rel.rotation * pp.pb.plane(fb).normal);
  }
  return axis;
}

// That face's manifold along the exact normal n (A's frame, A -> B) with
// exact rounded depths; `exact`: penetration()'s point (world), added when
// every clipped point is shallower (null when n is the face's normal and
// the closest points lie inside the face). False when the face has none (a
// face too large for the buffers, no point kept).
bool rounded_face_manifold(const PolytopePair& pp, const WorldFrame& world, const SatAxis& face, const Vec& n,
                           const ContactResult* exact, ContactResult& out) {
  const Ties ties{pp.band, geometric_tolerance(pp.scale), pp.last, pp.hold};
  const double ra = pp.ra, rb = pp.rb;
  CandidateList candidates;
  const bool of_a = face.kind == SatAxisKind::face_a;
  const Vec along = of_a ? n : Vec(-n);  // out of the reference
  const SatPolytope& ref = of_a ? pp.pa : pp.pb;
  const SatPolytope& inc = of_a ? pp.pb : pp.pa;
  const Placement& ref_place = of_a ? pp.identity : pp.placed_b;
  const Placement& inc_place = of_a ? pp.placed_b : pp.identity;
  const Index ref_face = of_a ? face.feature_a : face.feature_b;
  out.path = of_a ? ContactPath::face_a : ContactPath::face_b;
  if (!face_contact(ref, ref_place, inc, inc_place, ref_face, of_a, ties, pp.keep + ra + rb, candidates,
                    out.stats.clipped_points, &along))
    return false;
  round_along(candidates, along, of_a, ref, ref_place, ref_face, of_a ? ra : rb, inc, inc_place,
              incident_face(inc, inc_place, along), of_a ? rb : ra);
  if (exact) add_witnesses_if_missed(*exact, world, pp.band, candidates);
  emit(candidates, n, 0.0, 0.0, pp.keep, ties, world, out);
  return out.count > 0;
}

// `single`: penetration()'s answer. `used`: the axis the manifold stands on
// (the face, or the edges at the support vertices: the next frame's cache).
ContactResult rounded_cores_apart(const PolytopePair& pp, const Pose& pose_a, const WorldFrame& world,
                                  const ContactResult& single, const ContactStats& stats,
                                  const ContactSettings& settings, SatAxis& used) {
  used = SatAxis{};
  if (single.count == 0 || single.status != Status::ok) return single;
  const Vec n = pose_a.rotation.transpose() * single.normal;  // A's core frame, A -> B
  used = rounded_face_along(pp, n, settings);
  if (used.kind != SatAxisKind::none) {
    ContactResult out;
    out.stats = stats;
    if (rounded_face_manifold(pp, world, used, n, &single, out)) {
      out.error_bound = detail::bound_within(out.distance, out.error_bound, single.distance, single.error_bound);
      return out;
    }
  } else {
    used.kind = SatAxisKind::edge;
    used.feature_a = edge_across(pp.pa, n);
    used.feature_b = edge_across(pp.pb, -(pp.rel.rotation.transpose() * n));
  }
  ContactResult r = single;
  r.stats = stats;
  return r;
}

// The cached axis certified exact with the cores apart (its separation s
// is their distance, its normal theirs): the manifold a cold query builds,
// the face's, or one point between the edges, without GJK. False when the
// cold query would do otherwise (then it runs).
bool rounded_apart_from_cache(const PolytopePair& pp, const WorldFrame& world, const SatAxis& axis,
                              const ContactSettings& settings, ContactResult& out) {
  const SatAxis face = rounded_face_along(pp, axis.normal, settings);
  if (axis.kind != SatAxisKind::edge) {
    // A face axis certified exact: its normal is the cores', their closest
    // points inside the face.
    return face.kind != SatAxisKind::none && rounded_face_manifold(pp, world, face, axis.normal, nullptr, out);
  }
  const auto [a0, a1, b0, b1] = edge_pair_ends(pp, axis.feature_a, axis.feature_b);
  Vec on_a, on_b;
  closest_segment_points(a0, a1 - a0, b0, b1 - b0, on_a, on_b);
  PenetrationResult p;  // as penetration() reports the rounded pair
  p.distance = axis.separation - pp.ra - pp.rb;
  p.normal = world.direction(axis.normal);
  p.point_a = world.point(on_a + pp.ra * axis.normal);
  p.point_b = world.point(on_b - pp.rb * axis.normal);
  p.error_bound = 3.0 * pp.band;  // the axis certified within the band, its supports within 2 band
  const ContactStats stats = out.stats;
  const ContactResult single = penetration_point(p, pp.shape_scale, settings);
  out.stats = stats;
  if (face.kind != SatAxisKind::none) return rounded_face_manifold(pp, world, face, axis.normal, &single, out);
  out = single;
  out.stats = stats;
  return true;
}

// The face axis of A nearest n among the faces around A's support vertex
// in n (of_a), or B's in -n (n: A's frame, A -> B): of the faces whose
// normals surround the exact normal, the one most nearly along it, its
// separation measured as SAT does (exact supports).
SatAxis face_near(const PolytopePair& pp, const Vec& n, bool of_a) {
  const SatPolytope& poly = of_a ? pp.pa : pp.pb;
  const Vec dir = of_a ? n : Vec(-(pp.rel.rotation.transpose() * n));
  Index face = hull::kInvalidIndex;
  double best = -std::numeric_limits<double>::infinity();
  for (const Index f : poly.mesh->vertex_faces(poly.support(dir))) {
    const double along = poly.plane(f).normal.dot(dir);
    if (along > best) {
      best = along;
      face = f;
    }
  }
  return face == hull::kInvalidIndex ? SatAxis{} : sat_face_axis(pp.pa, pp.pb, pp.rel, of_a, face);
}

// The three candidate axes of a pair that is not separated beyond the
// contact distance: the best face of A, of B, and the edge axis.
struct AxisCandidates {
  SatAxis face_a, face_b, edge;
};

using detail::choose_axis;  // contact_choice.hpp: the face bias and B's kept face

void remember(ContactCache* cache, const SatAxis& axis) {
  if (!cache) return;
  cache->axis = axis.kind;
  cache->feature = axis.kind == SatAxisKind::face_b ? axis.feature_b : axis.feature_a;
  cache->feature_b = axis.kind == SatAxisKind::edge ? axis.feature_b : hull::kInvalidIndex;
}

ContactResult separated_along(const PolytopePair& pp, const WorldFrame& world, const SatAxis& axis,
                              const ContactStats& stats) {
  ContactResult out;
  out.stats = stats;
  out.path = ContactPath::separated;
  out.distance = axis.separation - pp.ra - pp.rb;
  out.normal = world.direction(axis.normal);
  out.intersecting = false;
  return out;
}

// The face or edge contact along the chosen axis (see manifold.hpp);
// `exact` is penetration()'s answer when the axis came from it (else null:
// computed here when a fallback needs it).
ContactResult build_manifold(const PolytopePair& pp, const WorldFrame& world, const SatAxis& best,
                             const ContactResult* exact, ContactCache* cache, const ContactSettings& settings,
                             const ContactStats& stats, double exact_limit) {
  const auto fallback = [&] {
    ContactResult single = exact ? *exact : single_point(pp, cache, settings);
    single.stats = stats;
    return single;
  };
  ContactResult out;
  out.stats = stats;
  CandidateList candidates;
  const double ra = pp.ra, rb = pp.rb;
  const Ties ties{pp.band, geometric_tolerance(pp.scale), pp.last, pp.hold};
  const bool rounded = ra + rb > 0.0;
  const double band = settings.penetration.touching_band * pp.scale;
  const bool apart = best.separation > band;  // SAT's separation: a lower bound on the cores' distance
  Vec normal = best.normal;
  bool built = false;
  if (best.kind == SatAxisKind::face_a) {
    out.path = ContactPath::face_a;
    built = face_contact(pp.pa, pp.identity, pp.pb, pp.placed_b, best.feature_a, true, ties, pp.core_contact,
                         candidates, out.stats.clipped_points);
    if (built && rounded)
      round_candidates(candidates, normal, true, ra, pp.pb, pp.placed_b, incident_face(pp.pb, pp.placed_b, normal), rb);
  } else if (best.kind == SatAxisKind::face_b) {
    out.path = ContactPath::face_b;
    built = face_contact(pp.pb, pp.placed_b, pp.pa, pp.identity, best.feature_b, false, ties, pp.core_contact,
                         candidates, out.stats.clipped_points);
    if (built && rounded)
      round_candidates(candidates, -normal, false, rb, pp.pa, pp.identity, incident_face(pp.pa, pp.identity, -normal),
                       ra);
  } else if (exact) {
    // The exact axis is no face axis: penetration()'s witnesses, named by
    // the edges they lie on.
    ContactResult r = *exact;
    r.stats = stats;
    if (r.count == 1 && best.feature_a != hull::kInvalidIndex && best.feature_b != hull::kInvalidIndex) {
      r.path = ContactPath::edge;
      r.points[0].id.kind = FeatureKind::edge;
      r.points[0].id.reference = best.feature_a;
      r.points[0].id.incident = best.feature_b;
    }
    return r;
  } else {
    out.path = ContactPath::edge;
    const Index ea = best.feature_a, eb = best.feature_b;
    const auto [a0, a1, b0, b1] = edge_pair_ends(pp, ea, eb);
    Vec on_a, on_b;
    closest_segment_points(a0, a1 - a0, b0, b1 - b0, on_a, on_b);
    FeatureId id;
    id.kind = FeatureKind::edge;
    id.reference = ea;
    id.incident = eb;
    // Apart, a closest point at an end of its edge lies farther than the
    // axis's separation: the points' own distance, for the check below.
    candidates.push(on_a, on_b, apart ? std::max(best.separation, (on_b - on_a).norm()) : best.separation, id);
    built = true;
  }
  const bool shifted = rounded && best.kind != SatAxisKind::edge;  // round_candidates moved them already
  double deepest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < candidates.size; ++i) deepest = std::min(deepest, candidates[i].separation);
  const double axis_separation = best.separation - (shifted ? ra + rb : 0.0);
  // Sharp cores apart: SAT's separation bounds their distance from below and
  // the nearest candidate's gap from above. Where these differ the closest
  // features are neither a face's interior nor crossing edges (an edge or a
  // vertex on each side), and the manifold follows the exact normal as for
  // rounded cores.
  if (apart && built && candidates.size > 0 && deepest > axis_separation + band) {
    SatAxis used;
    const ContactResult r = rounded_cores_apart(pp, *pp.pose_a, world, fallback(), stats, settings, used);
    remember(cache, used);
    return r;
  }
  // A face too large for the fixed buffers, or an incident face entirely
  // outside the reference face's side planes: one point from penetration().
  if (!built || candidates.size == 0) return fallback();
  // The incident shape's deepest vertex clipped away by the reference face's
  // side planes (contact_depth.hpp): no point on the two surfaces is as deep
  // as the overlap along the axis, so the exact normal decides.
  const double held = pp.last ? pp.hold : 0.0;
  if (detail::deepest_short_of_axis(deepest, axis_separation, exact_limit - (shifted ? ra + rb : 0.0), pp.band, held)) {
    SatAxis used;
    const ContactResult r = rounded_cores_apart(pp, *pp.pose_a, world, fallback(), stats, settings, used);
    remember(cache, used);
    return r;
  }
  emit(candidates, normal, shifted ? 0.0 : ra, shifted ? 0.0 : rb, pp.keep, ties, world, out);
  if (out.count == 0) {
    // Nothing within the contact distance after clipping (a gap along the
    // chosen axis beyond it): report the axis.
    out.distance = best.separation - ra - rb;
    out.normal = world.direction(normal);
    out.intersecting = false;
  }
  return out;
}

// ---- the cached face axis, certified --------------------------------------
//
// A face axis (normal u, A's frame, A -> B; separation s) measures one facet
// of the Minkowski difference D = B - A: the face against the other shape's
// support vertex, in the plane u . x = s, every other point of D having
// u . x >= s. SAT's largest separation s* (penetration()'s signed distance)
// is at least s. It is at most s + tol when
//   * s >= 0: the origin's foot s u on that plane lies in the facet (a point
//     of D at distance s: the distance is at most s), or
//   * s < 0: the pyramid of the facet and D's support point along u (inside
//     D: D is convex) holds the ball of radius |s| - tol about the origin
//     (every side plane at least that far), so the depth is at least that.
// Then the axis is (to tol) the exact one, the axis a cold query chooses
// (every other axis separates by at most s* <= s + tol, short of the bias),
// and the manifold is built from it without SAT's search or GJK/EPA.

// The facet's vertices (polygon order; at most out.size()), or 0.
std::size_t axis_facet(const PolytopePair& pp, const SatAxis& axis, std::array<Vec, kClipCapacity>& out) {
  const bool of_a = axis.kind == SatAxisKind::face_a;
  const SatPolytope& ref = of_a ? pp.pa : pp.pb;
  const hull::HalfEdgeMesh& m = *ref.mesh;
  const Index face = of_a ? axis.feature_a : axis.feature_b;
  if (m.face_degree(face) > out.size()) return 0;
  std::size_t count = 0;
  if (of_a) {  // B's support vertex minus the face's vertices
    const Vec b = pp.placed_b.point(pp.pb.vertex(pp.pb.support(-(pp.rel.rotation.transpose() * axis.normal))));
    for (const Index e : m.face_edges(face)) out[count++] = b - pp.pa.vertex(m.origin(e));
  } else {  // the face's vertices minus A's support vertex
    const Vec a = pp.pa.vertex(pp.pa.support(axis.normal));
    for (const Index e : m.face_edges(face)) out[count++] = pp.placed_b.point(pp.pb.vertex(m.origin(e))) - a;
  }
  return count;
}

// D's support point along u: B's along u minus A's along -u. `far_a`,
// `far_b`: the supports' climb starts on the far sides, kept apart from the
// near sides' so neither climb crosses a hull.
Vec far_apex(const PolytopePair& pp, const Vec& u, Index& far_a, Index& far_b) {
  const Index near_a = pp.pa.hint, near_b = pp.pb.hint;
  if (far_a < pp.pa.mesh->vertex_count()) pp.pa.hint = far_a;
  if (far_b < pp.pb.mesh->vertex_count()) pp.pb.hint = far_b;
  const Vec apex =
      pp.placed_b.point(pp.pb.vertex(pp.pb.support(pp.rel.rotation.transpose() * u))) - pp.pa.vertex(pp.pa.support(-u));
  far_a = pp.pa.hint;
  far_b = pp.pb.hint;
  pp.pa.hint = near_a;
  pp.pb.hint = near_b;
  return apex;
}

// The face axis's facet of D as two polygons whose sums are points b - a:
// B's side and A's negated, one the reference face's vertices, the other
// the incident face's within tol / 2 of the support level along the axis
// (face_certificate.hpp); false when they do not fit.
bool minkowski_facet(const PolytopePair& pp, const SatAxis& axis, double tol, detail::FacetSide& b_side,
                     detail::FacetSide& a_side) {
  const bool of_a = axis.kind == SatAxisKind::face_a;
  const SatPolytope& ref = of_a ? pp.pa : pp.pb;
  const SatPolytope& inc = of_a ? pp.pb : pp.pa;
  const Placement& ref_place = of_a ? pp.identity : pp.placed_b;
  const Placement& inc_place = of_a ? pp.placed_b : pp.identity;
  const Index face = of_a ? axis.feature_a : axis.feature_b;
  const Vec out_of_ref = of_a ? axis.normal : Vec(-axis.normal);
  const Index inc_face = incident_face(inc, inc_place, out_of_ref);
  if (inc_face == hull::kInvalidIndex) return false;
  const hull::HalfEdgeMesh& rm = *ref.mesh;
  const hull::HalfEdgeMesh& im = *inc.mesh;
  if (rm.face_degree(face) > detail::kFacetCapacity || im.face_degree(inc_face) > detail::kFacetCapacity) return false;
  detail::FacetSide& ref_side = of_a ? a_side : b_side;
  detail::FacetSide& inc_side = of_a ? b_side : a_side;
  const double sign_ref = of_a ? -1.0 : 1.0;  // A's side enters negated
  ref_side.count = 0;
  for (const Index e : rm.face_edges(face))
    ref_side.p[ref_side.count++] = sign_ref * ref_place.point(ref.vertex(rm.origin(e)));
  // The incident face's vertices at the support level (lowest along the
  // reference's outward normal), in the face's order.
  std::array<double, detail::kFacetCapacity> height;
  inc_side.count = 0;
  double lowest = std::numeric_limits<double>::infinity();
  for (const Index e : im.face_edges(inc_face)) {
    const Vec x = inc_place.point(inc.vertex(im.origin(e)));
    height[inc_side.count] = out_of_ref.dot(x);
    lowest = std::min(lowest, height[inc_side.count]);
    inc_side.p[inc_side.count++] = -sign_ref * x;
  }
  std::size_t kept = 0;
  for (std::size_t j = 0; j < inc_side.count; ++j)
    if (height[j] <= lowest + 0.5 * tol) inc_side.p[kept++] = inc_side.p[j];
  inc_side.count = kept;
  return true;
}

// True when the separation s of the facet (count points of D in the plane
// u . x = s, polygon order) is certified to be SAT's largest within tol
// (see above).
// `far_a`, `far_b`: the supports' climb starts on the far sides (the
// apex's), kept apart from the near sides' so neither climb crosses a hull.
bool facet_is_exact(const PolytopePair& pp, const std::array<Vec, kClipCapacity>& facet, std::size_t count,
                    const Vec& u, double s, double tol, Index& far_a, Index& far_b) {
  if (count < 3) return false;
  Vec centroid = Vec::Zero();
  for (std::size_t k = 0; k < count; ++k) centroid += facet[k];
  centroid /= static_cast<double>(count);
  if (s >= 0.0) {
    const Vec foot = s * u;
    for (std::size_t k = 0; k < count; ++k) {
      const Vec& p = facet[k];
      Vec side = (facet[k + 1 == count ? 0 : k + 1] - p).cross(u);
      if (side.dot(centroid - p) > 0.0) side = -side;  // outward
      if (side.dot(foot - p) > 0.0) return false;
    }
    return true;
  }
  const Vec apex = far_apex(pp, u, far_a, far_b);
  const Vec inside = 0.5 * (centroid + apex);
  const double need = -s - tol;
  for (std::size_t k = 0; k < count; ++k) {
    const Vec& p = facet[k];
    Vec side = (facet[k + 1 == count ? 0 : k + 1] - p).cross(apex - p);
    const double len = side.norm();
    if (!(len > 0.0)) return false;
    if (side.dot(inside - p) > 0.0) side = -side;    // outward
    if (!(side.dot(p) >= need * len)) return false;  // the origin's distance inside this side
  }
  return true;
}

// The cached edge pair's axis at the new poses, N = e_A x e_B turned so
// that the two edges are the shapes' supports along it (A's at its top, B's
// at its bottom, within tol); kind none when the edges have turned
// parallel or no longer support the shapes. `facet`: the parallelogram
// e_B - e_A, D's facet along N.
SatAxis cached_edge_axis(const PolytopePair& pp, const ContactCache& cache, const ContactSettings& settings, double tol,
                         std::array<Vec, kClipCapacity>& facet) {
  const hull::HalfEdgeMesh& ma = *pp.pa.mesh;
  const hull::HalfEdgeMesh& mb = *pp.pb.mesh;
  const Index ea = cache.feature, eb = cache.feature_b;
  if (ea >= ma.half_edge_count() || eb >= mb.half_edge_count()) return {};
  const auto [a0, a1, b0, b1] = edge_pair_ends(pp, ea, eb);
  Vec u = (a1 - a0).cross(b1 - b0);
  const double len = u.norm();
  if (!(len > settings.parallel_tolerance * (a1 - a0).norm() * (b1 - b0).norm())) return {};
  u /= len;
  const auto supports = [&](const Vec& n) {
    const Vec a_top = pp.pa.vertex(pp.pa.support(n));
    const Vec b_low = pp.placed_b.point(pp.pb.vertex(pp.pb.support(-(pp.rel.rotation.transpose() * n))));
    return n.dot(a_top - a0) <= tol && n.dot(b0 - b_low) <= tol;
  };
  if (!supports(u)) {
    u = -u;
    if (!supports(u)) return {};
  }
  facet[0] = b0 - a0;
  facet[1] = b1 - a0;
  facet[2] = b1 - a1;
  facet[3] = b0 - a1;
  SatAxis axis;
  axis.kind = SatAxisKind::edge;
  axis.separation = u.dot(b0 - a0);
  axis.feature_a = ea;
  axis.feature_b = eb;
  axis.normal = u;
  return axis;
}

// The manifold of the chosen axis (choose_axis), remembered in the cache.
// When the cache's kept face of B builds no manifold of its own (its kept
// points too shallow: penetration()'s single point would follow), the
// choice without the cache is built instead, as a cold query builds it.
ContactResult build_chosen(const PolytopePair& pp, const WorldFrame& world, const AxisCandidates& c,
                           const ContactResult* exact, ContactCache* cache, const ContactSettings& settings,
                           const ContactStats& stats, double exact_limit) {
  const SatAxis best = choose_axis(c, cache, settings, pp.scale);
  remember(cache, best);
  ContactResult r = build_manifold(pp, world, best, exact, cache, settings, stats, exact_limit);
  const SatAxis cold = choose_axis(c, nullptr, settings, pp.scale);
  if (r.path != ContactPath::single_point || cold.kind == best.kind) return r;
  remember(cache, cold);
  return build_manifold(pp, world, cold, exact, cache, settings, stats, exact_limit);
}

// SAT's axes: the full separating-axis test (sat.hpp).
ContactResult contact_by_sat(const PolytopePair& pp, const WorldFrame& world, ContactCache* cache,
                             const ContactSettings& settings) {
  SatSettings sat;
  sat.parallel_tolerance = settings.parallel_tolerance;
  sat.early_out = pp.core_contact;
  const SatResult s = sat_query(pp.pa, pp.pb, pp.rel, sat);
  ContactStats stats;
  stats.edge_pairs = s.edge_pairs;
  if (s.separated) {
    // The axis that proved it is the best one seen last.
    const SatAxis* axis = &s.face_a;
    if (s.face_b.separation > axis->separation) axis = &s.face_b;
    if (s.edge.separation > axis->separation) axis = &s.edge;
    remember(cache, *axis);
    return separated_along(pp, world, *axis, stats);
  }
  const AxisCandidates c{s.face_a, s.face_b, s.edge};
  const SatAxis best = choose_axis(c, cache, settings, pp.scale);
  if (pp.ra + pp.rb > 0.0 && best.separation > settings.penetration.touching_band * pp.scale) {
    const ContactResult single = single_point(pp, cache, settings);
    SatAxis used;
    const ContactResult r = rounded_cores_apart(pp, *pp.pose_a, world, single, stats, settings, used);
    remember(cache, used);
    return r;
  }
  // Overlapping or touching cores: SAT's largest separation is exact.
  const double largest = std::max({s.face_a.separation, s.face_b.separation, s.edge.separation});
  const double band = settings.penetration.touching_band * pp.scale;
  const double limit = largest <= band ? largest + band : std::numeric_limits<double>::infinity();
  ContactResult r = build_chosen(pp, world, c, nullptr, cache, settings, stats, limit);
  // Cores overlapping: SAT's largest separation is the exact one; apart
  // (within the contact distance), it is a lower bound and the reported
  // distance, two surface points' gap, an upper one.
  if (r.count > 0 || largest <= band)
    r.error_bound = detail::bound_within(r.distance, r.error_bound, largest - pp.ra - pp.rb, 0.0);
  return r;
}

// The exact normal's axes: penetration() (GJK, EPA when the cores overlap)
// gives the exact separation s* and normal n; the face candidates are, on
// each side, the face at the support vertex along n most nearly along n
// (its separation measured as SAT does), and the edge axis is n itself with
// s*, named by the
// edges at the support vertices most nearly perpendicular to n. The same
// bias then chooses among them. SAT's largest separation is s*, so this is
// SAT's answer up to which face wins within the bias, without SAT's
// E_A x E_B edge pairs.
ContactResult contact_by_normal(const PolytopePair& pp, const WorldFrame& world, ContactCache* cache,
                                const ContactSettings& settings) {
  const PenetrationResult p = pp.penetration(cache, settings);
  const ContactResult exact = penetration_point(p, pp.shape_scale, settings);
  if (p.status == Status::degenerate || p.status == Status::invalid_input) return exact;
  const Vec n = pp.pose_a->rotation.transpose() * p.normal;  // A's core frame, A -> B
  if (exact.count == 0) {
    // Separated beyond the contact distance: with a cache, remember a face
    // that separates (the next frame's early out), else nothing.
    if (cache) {
      const SatAxis face_a = face_near(pp, n, true), face_b = face_near(pp, n, false);
      const SatAxis& face = face_b.separation > face_a.separation ? face_b : face_a;
      remember(cache, face.separation > pp.core_contact ? face : SatAxis{});
    }
    return exact;
  }
  const double s_exact = p.distance + pp.ra + pp.rb;  // between the cores
  if (pp.ra + pp.rb > 0.0 && s_exact > settings.penetration.touching_band * pp.scale) {
    SatAxis used;
    const ContactResult r = rounded_cores_apart(pp, *pp.pose_a, world, exact, ContactStats{}, settings, used);
    remember(cache, used);
    return r;
  }
  AxisCandidates c;
  c.face_a = face_near(pp, n, true);
  c.face_b = face_near(pp, n, false);
  c.edge.kind = SatAxisKind::edge;
  c.edge.separation = s_exact;
  c.edge.normal = n;
  c.edge.feature_a = edge_across(pp.pa, n);
  c.edge.feature_b = edge_across(pp.pb, -(pp.rel.rotation.transpose() * n));
  const double limit = s_exact + p.error_bound + settings.penetration.touching_band * pp.scale;
  ContactResult r = build_chosen(pp, world, c, &exact, cache, settings, ContactStats{}, limit);
  r.error_bound = detail::bound_within(r.distance, r.error_bound, p.distance, p.error_bound);
  return r;
}

// The cached axis certified exact within tol at the new poses: an edge pair
// by `facet`; a face axis by the support vertex's facet, else by its
// Minkowski facet (face_certificate.hpp: a body resting face on face has
// the two faces' sum as its facet, whose rim the origin lies far from).
bool axis_is_exact(const PolytopePair& pp, const SatAxis& axis, std::array<Vec, kClipCapacity>& facet,
                   std::size_t count, double tol, ContactCache& cache) {
  if (axis.kind != SatAxisKind::edge) {
    if (axis.separation > pp.core_contact) return false;
    // The support vertex's facet first (cheap: the reference face's
    // translate); the two faces' sum when it does not suffice.
    count = axis_facet(pp, axis, facet);
    if (facet_is_exact(pp, facet, count, axis.normal, axis.separation, tol, cache.far_a, cache.far_b)) return true;
    detail::FacetSide b_side, a_side;
    if (!minkowski_facet(pp, axis, tol, b_side, a_side)) return false;
    const Vec apex = axis.separation < 0.0 ? far_apex(pp, axis.normal, cache.far_a, cache.far_b) : Vec(Vec::Zero());
    return detail::facet_certifies(b_side, a_side, axis.normal, axis.separation, tol, apex);
  }
  return facet_is_exact(pp, facet, count, axis.normal, axis.separation, tol, cache.far_a, cache.far_b);
}

// What the last frame learned: the cached axis (a face, or an edge pair)
// re-measured at the new poses, before any search.
//   * Separated beyond the contact distance along it: answered from that
//     axis alone (separated; the distance a lower bound, as SAT's).
//   * Certified exact (facet_is_exact): the manifold a cold query builds
//     on it, without SAT or GJK/EPA: a face's, or an edge pair's against
//     the faces about its axis (the bias), or for rounded cores apart the
//     face or edge point along their exact normal. Rounded cores apart by
//     less than the certificate's tolerance are left to the cold query
//     (which side of the touching band they fall on is not certain).
// False when the cold query must run.
bool answer_from_cache(const PolytopePair& pp, const WorldFrame& world, ContactCache* cache,
                       const ContactSettings& settings, ContactResult& out) {
  if (!cache) return false;
  const double band = settings.penetration.touching_band * pp.scale;
  std::array<Vec, kClipCapacity> facet;
  SatAxis axis;
  std::size_t count = 0;
  if (cache->axis == SatAxisKind::face_a || cache->axis == SatAxisKind::face_b) {
    const bool of_a = cache->axis == SatAxisKind::face_a;
    if (cache->feature >= (of_a ? pp.pa.mesh->face_count() : pp.pb.mesh->face_count())) return false;
    axis = sat_face_axis(pp.pa, pp.pb, pp.rel, of_a, cache->feature);
  } else if (cache->axis == SatAxisKind::edge) {
    axis = cached_edge_axis(pp, *cache, settings, band, facet);
    count = 4;
  }
  if (axis.kind == SatAxisKind::none) return false;
  ContactStats hit;
  hit.cache_hit = true;
  // (An edge pair's supports hold within 2 band: its separation is SAT's
  // less that much.)
  if (axis.separation - (axis.kind == SatAxisKind::edge ? 2.0 * band : 0.0) > pp.core_contact) {
    out = separated_along(pp, world, axis, hit);
    return true;
  }
  // A face axis with the cores overlapping or touching is kept while it is
  // certified within choose_axis's bias of SAT's largest separation (no
  // challenger could beat it: the axis a cold query keeps, up to another
  // face of the same shape within the bias); an edge axis, or cores apart
  // (the manifold then follows their exact normal), within the band.
  const bool biased = axis.kind != SatAxisKind::edge && axis.separation <= band;
  const double tol =
      biased ? settings.relative_bias * std::abs(axis.separation) + settings.absolute_bias * pp.scale : band;
  if (!axis_is_exact(pp, axis, facet, count, tol, *cache)) return false;
  out.stats = hit;
  if (pp.ra + pp.rb > 0.0 && axis.separation > 0.0) {
    if (!(axis.separation > band)) return false;
    if (!rounded_apart_from_cache(pp, world, axis, settings, out)) return false;
    remember(cache, axis.kind == SatAxisKind::edge ? axis : rounded_face_along(pp, axis.normal, settings));
    out.error_bound = detail::bound_within(out.distance, out.error_bound, axis.separation - pp.ra - pp.rb, 3.0 * band);
    return true;
  }
  if (axis.kind != SatAxisKind::edge) {
    out = build_manifold(pp, world, axis, nullptr, cache, settings, hit, axis.separation + tol + band);
    // Certified: the cores' exact separation lies in [s, s + tol].
    out.error_bound =
        detail::bound_within(out.distance, out.error_bound, axis.separation + 0.5 * tol - pp.ra - pp.rb, 0.5 * tol);
    return true;
  }
  const AxisCandidates c{face_near(pp, axis.normal, true), face_near(pp, axis.normal, false), axis};
  out = build_chosen(pp, world, c, nullptr, cache, settings, hit, axis.separation + 2.0 * band);
  // Certified within the band; the edge pair's supports within 2 band.
  out.error_bound = detail::bound_within(out.distance, out.error_bound, axis.separation - pp.ra - pp.rb, 3.0 * band);
  return true;
}

// SAT's edge loop tests E_A x E_B edge pairs; the exact normal costs
// penetration() and a few face measurements. Which one runs.
bool use_sat(const PolytopePair& pp, const ContactSettings& settings) {
  switch (settings.axis_search) {
    case PolytopeAxisSearch::sat:
      return true;
    case PolytopeAxisSearch::exact_normal:
      return false;
    case PolytopeAxisSearch::automatic:
      break;
  }
  const double pairs = static_cast<double>(pp.pa.mesh->edge_count()) * static_cast<double>(pp.pb.mesh->edge_count());
  return pairs <= settings.max_sat_edge_pairs;
}

}  // namespace

// penetration()'s answer as the pair's one point.
ContactResult single_point(const PolytopePair& pp, ContactCache* cache, const ContactSettings& settings) {
  return penetration_point(pp.penetration(cache, settings), pp.shape_scale, settings);
}

// The polytope path on a ready pair: the cached axis first, else the
// search the settings choose.
ContactResult polytope_manifold(PolytopePair& pp, const WorldFrame& world, ContactCache* cache,
                                const ContactSettings& settings) {
  if (cache && pp.pa.poly && cache->support_a < pp.pa.mesh->vertex_count()) pp.pa.hint = cache->support_a;
  if (cache && pp.pb.poly && cache->support_b < pp.pb.mesh->vertex_count()) pp.pb.hint = cache->support_b;
  const auto stored = [&](ContactResult r) {
    if (cache) {
      cache->support_a = pp.pa.hint;
      cache->support_b = pp.pb.hint;
      cache->kept_count = r.count;
      for (int k = 0; k < r.count; ++k) cache->kept[k] = r.points[k].id;
    }
    return r;
  };
  ContactResult warm;
  if (answer_from_cache(pp, world, cache, settings, warm)) return stored(warm);
  if (use_sat(pp, settings)) return stored(contact_by_sat(pp, world, cache, settings));
  return stored(contact_by_normal(pp, world, cache, settings));
}

}  // namespace hedra::collision::detail::manifold
