// Clipping and reduction, shared by the contact paths: an incident face
// clipped by the side planes of a reference face's edges (hull::clip_polygon,
// fixed buffers), each kept point named by the features that make it, the
// candidates reduced to four (the deepest, the farthest from it, the largest
// triangle areas on each side, each the first within a tie of the best), the
// rounded surfaces' exits, and the world result (emit). docs/contacts.md
// describes the choices; emit() asserts each depth is the gap along the
// normal.
#include <algorithm>
#include <cmath>
#include <hedra/hull/assert.hpp>
#include <hedra/hull/mesh_edit.hpp>
#include <limits>

#include "contact_choice.hpp"
#include "contact_common.hpp"

namespace hedra::collision::detail::manifold {

namespace {

// The first candidate (in the clipped polygon's order) whose value is within
// `tie` of the largest: a choice that depth or position noise below the tie
// does not move from one point to another.
template <class Value>
std::size_t first_near_largest(const CandidateList& c, double tie, Value value) {
  double best = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < c.size; ++i) best = std::max(best, value(i));
  for (std::size_t i = 0; i < c.size; ++i)
    if (value(i) >= best - tie) return i;
  return 0;
}

}  // namespace

// Reduction to at most four points (see manifold.hpp): the deepest, the
// farthest from it, then the largest positive and the largest negative
// signed areas of the triangle they make with a third point (about n).
// Each choice takes the first candidate within the ties of the best (a
// resting hexagon's six equally deep corners, its two equal triangles on
// each side), so the kept points do not swap with noise in the depths or
// positions: the deepest kept is at most ties.depth shallower than the
// deepest candidate.
int reduce(const CandidateList& c, const Vec& n, const Ties& ties, std::array<std::size_t, kMaxContactPoints>& keep) {
  if (c.size == 0) return 0;
  const std::size_t i0 = first_near_largest(c, ties.depth, [&](std::size_t i) { return -c[i].separation; });
  keep[0] = i0;
  if (c.size == 1) return 1;
  const Vec p0 = c[i0].on_b;
  const std::size_t i1 = first_near_largest(c, ties.length, [&](std::size_t i) { return (c[i].on_b - p0).norm(); });
  const double far = (c[i1].on_b - p0).squaredNorm();
  if (!(far > 0.0)) return 1;  // all candidates coincide
  keep[1] = i1;
  const Vec p1 = c[i1].on_b;
  const auto area = [&](std::size_t i) { return (p0 - c[i].on_b).cross(p1 - c[i].on_b).dot(n); };
  // Areas below this (relative to the span) add nothing: collinear points.
  const double min_area = 1e-9 * far, area_tie = ties.length * std::sqrt(far);
  const std::size_t i2 = first_near_largest(c, area_tie, area);
  const std::size_t i3 = first_near_largest(c, area_tie, [&](std::size_t i) { return -area(i); });
  int count = 2;
  if (area(i2) > min_area) keep[count++] = i2;
  if (-area(i3) > min_area) keep[count++] = i3;
  return count;
}

// Shifts the cores' candidates by the radii, keeps those separated by at
// most max_separation (the contact distance and the touching band),
// reduces to four and writes the world result.
void emit(CandidateList& c, const Vec& normal, double radius_a, double radius_b, double max_separation,
          const Ties& ties, const WorldFrame& world, ContactResult& out) {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < c.size; ++i) {
    Candidate x = c[i];
    x.separation -= radius_a + radius_b;
    if (!(x.separation <= max_separation)) continue;
    x.on_a += radius_a * normal;
    x.on_b -= radius_b * normal;
    c[kept++] = x;
  }
  c.size = kept;
  std::array<std::size_t, kMaxContactPoints> keep{};
  if (c.size <= static_cast<std::size_t>(kMaxContactPoints)) {
    // Already reduced (face contacts reduce before their feature ids): keep
    // all, the deepest first.
    out.count = static_cast<int>(c.size);
    for (int k = 0; k < out.count; ++k) keep[k] = static_cast<std::size_t>(k);
    for (int k = 1; k < out.count; ++k)
      if (c[keep[k]].separation < c[keep[0]].separation) std::swap(keep[0], keep[k]);
  } else {
    out.count = reduce(c, normal, ties, keep);
  }
  HEDRA_ASSERT(out.count >= 0 && out.count <= kMaxContactPoints);
  HEDRA_ASSERT(std::abs(normal.squaredNorm() - 1.0) <= 1e-9);  // manifold.hpp: a unit normal
  out.normal = world.direction(normal);
  for (int k = 0; k < out.count; ++k) {
    const Candidate& x = c[keep[k]];
    // Each depth is the gap along the normal: the witnesses differ by the
    // separation along it. Exact by construction (on_ref = p - s n, both
    // moved along n by the rounding) but for an edge pair apart, whose
    // closest points may lie off the axis by up to sqrt(2 s band) (the
    // check in build_manifold: their distance is within the band of s),
    // 1e-5 of the size at a contact distance of 2 % of it.
    HEDRA_ASSERT((x.on_b - x.on_a - x.separation * normal).norm() <= 10.0 * ties.length);
    out.points[k].point = world.point(0.5 * (x.on_a + x.on_b));
    out.points[k].depth = -x.separation;
    out.points[k].id = x.id;
  }
  if (out.count > 0) {
    const Candidate& deepest = c[keep[0]];
    out.distance = deepest.separation;
    out.point_a = world.point(deepest.on_a);
    out.point_b = world.point(deepest.on_b);
  }
  out.intersecting = out.count > 0 && out.distance <= 0.0;
}

// The incident face for a reference normal n (A's frame, out of the
// reference): the face most anti-parallel to n around inc's support vertex
// in -n.
Index incident_face(const SatPolytope& inc, const Placement& inc_place, const Vec& n) {
  const Vec m = inc_place.rotation.transpose() * n;  // n in inc's frame
  const Index v = inc.support(-m);
  Index face = hull::kInvalidIndex;
  double best = std::numeric_limits<double>::infinity();
  for (const Index g : inc.mesh->vertex_faces(v)) {
    const double dot = inc.plane(g).normal.dot(m);
    if (dot < best) {
      best = dot;
      face = g;
    }
  }
  return face;
}

using detail::segment_exit;  // contact_choice.hpp

// How far the ray p + t d (p on face f of a core, d unit, A's frame) runs
// inside the core grown by radius r. The grown core is the union of the
// faces' slabs, the edges' cylinders and the vertices' balls, a convex
// union: the ray leaves it where it leaves the last of them. Near p (within
// about r) only face f, its edges, its vertices and the faces around them
// can hold that exit; at least r (p is on the core), exactly r when d is
// in the core's normal cone at p.
double exit_distance(const SatPolytope& poly, const Placement& place, Index f, const Vec& p_in, const Vec& d_in,
                     double r) {
  const hull::HalfEdgeMesh& m = *poly.mesh;
  // In poly's own frame (the exit is the same in any frame): no vertex,
  // plane or normal placed per test.
  const Vec p = place.rotation.transpose() * (p_in - place.translation);
  const Vec d = place.rotation.transpose() * d_in;
  double t = r;
  double t_f = std::numeric_limits<double>::infinity();  // the exit from f's slab (a bound: the grown core lies in it)
  auto slab = [&](Index g) {
    const Vec& n = poly.plane(g).normal;
    const double nd = n.dot(d);
    if (!(nd > 0.0)) return false;
    const double ts = (poly.plane(g).offset - n.dot(p) + r) / nd;
    if (g == f) t_f = ts;
    const Vec foot = p + ts * d - r * n;
    for (const Index e : m.face_edges(g)) {
      const Vec& a = poly.vertex(m.origin(e));
      const Vec side = (poly.vertex(m.destination(e)) - a).cross(n);
      // The foot leaves face g (an edge or a vertex holds the exit), or it
      // overflowed (d almost along g's plane: no exit through g's slab).
      if (!(side.dot(foot - a) <= 0.0)) return false;
    }
    t = std::max(t, ts);
    return true;
  };
  // The common case first: the exit through face f's own slab, its foot
  // inside f, is a point at distance r from the core (its closest point the
  // foot), on the grown core's boundary: the ray, starting inside that
  // convex set, leaves it there and nowhere else.
  if (slab(f)) return t;
  // At a vertex of f with d in its normal cone (no neighbour higher along
  // d: the vertex is the core's support point along d, convexity), the
  // point r along d is r from the core: the exit is r.
  for (const Index e : m.face_edges(f)) {
    const Index v = m.origin(e);
    if (place.point(poly.vertex(v)) != p_in) continue;
    bool highest = true;
    for (const Index out : m.vertex_outgoing(v))
      if (d.dot(poly.vertex(m.destination(out)) - poly.vertex(v)) > 0.0) {
        highest = false;
        break;
      }
    if (highest) return r;
    break;
  }
  // Where the exit's closest point on the core lies: within reach of p. The
  // projection onto the core is 1-Lipschitz and keeps p + s n_f at p (n_f
  // is in the normal cone at every point of f), and the exit lies at most
  // t_f along d, so that point is within t_f |d - n_f| of p (plus p's own
  // rounding off f): a piece whose feature lies farther holds no exit. A
  // direction tilted 1e-6 rad off the face leaves only the pieces at p.
  const double reach = t_f * (d - poly.plane(f).normal).norm() + 1e-6 * r;  // infinite when d leaves f's side
  // Each face around the face's vertices once (a face shares several of
  // them; past the buffer, repeats are harmless).
  std::array<Index, 64> seen;
  std::size_t seen_count = 0;
  const auto first_visit = [&](Index g) {
    for (std::size_t k = 0; k < seen_count; ++k)
      if (seen[k] == g) return false;
    if (seen_count < seen.size()) seen[seen_count++] = g;
    return true;
  };
  for (const Index e : m.face_edges(f)) {
    const Vec& a = poly.vertex(m.origin(e));
    const Vec& b = poly.vertex(m.destination(e));
    const Vec ab = b - a;
    const double along = ab.squaredNorm() > 0.0 ? std::clamp(ab.dot(p - a) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    if (!((a + along * ab - p).norm() > reach)) t = std::max(t, segment_exit(p, d, a, b, r));
    // The faces around a that can come within reach of p: p near a, or
    // near an edge of f at a (both of whose faces are around its other end
    // too, visited from there when p is near it).
    if (!((a - p).norm() - ab.norm() > reach))
      for (const Index g : m.vertex_faces(m.origin(e)))
        // p's distance to g's plane (p inside the core) within reach.
        if (g != f && poly.plane(g).offset - poly.plane(g).normal.dot(p) <= reach && first_visit(g)) slab(g);
  }
  return t;
}

namespace {

// The half-edge of face f leaving the face's vertex nearest x (A's frame):
// the name of a corner of the reference face.
Index corner_edge(const SatPolytope& poly, const Placement& place, Index f, const Vec& x) {
  const hull::HalfEdgeMesh& m = *poly.mesh;
  Index corner = hull::kInvalidIndex;
  double best = std::numeric_limits<double>::infinity();
  for (const Index e : m.face_edges(f)) {
    const double d = (place.point(poly.vertex(m.origin(e))) - x).squaredNorm();
    if (d < best) {
      best = d;
      corner = e;
    }
  }
  return corner;
}

// The last frame's kept points (ties.last), when every one is still a
// candidate and the deepest of them is within ties.hold of the deepest
// candidate: a resting polygon's depths move by 1e-6 to 1e-4 of the size
// frame to frame with a solver's corrections, and the cold choice (the
// deepest first) would swap points every few frames. Else the cold choice.
template <class IdOf>
int hold_last(const CandidateList& c, const Vec& n, const Ties& ties, const IdOf& id_of,
              std::array<std::size_t, kMaxContactPoints>& keep, int kept) {
  const ContactCache& last = *ties.last;
  if (last.kept_count != kept) return kept;
  std::array<std::size_t, kMaxContactPoints> held{};
  int found = 0;
  double deepest = std::numeric_limits<double>::infinity(), deepest_held = deepest;
  for (std::size_t i = 0; i < c.size; ++i) {
    deepest = std::min(deepest, c[i].separation);
    const FeatureId id = id_of(c[i].on_b, Vec(c[i].on_b - c[i].separation * n));
    for (int k = 0; k < last.kept_count; ++k)
      if (last.kept[k] == id && found < kMaxContactPoints) {
        held[found++] = i;
        deepest_held = std::min(deepest_held, c[i].separation);
      }
  }
  if (found != kept || !(deepest_held <= deepest + ties.hold)) return kept;
  // The cold choice's own points: its order (a cold query's answer).
  int same = 0;
  for (int k = 0; k < kept; ++k) same += std::count(keep.begin(), keep.begin() + kept, held[k]) > 0;
  if (same < kept) keep = held;
  return kept;
}

}  // namespace

// Face contact: reference face `ref_face` of `ref`, incident face searched
// around inc's support vertex. Candidates' on_a / on_b follow A and B
// (ref_is_a says which is which). `along` (A's frame, out of ref, unit;
// null: the face's normal) is the direction the points are measured along:
// the side planes are swept along it, and each separation is the gap along
// it from the reference plane. Returns false when a face is too large for
// the fixed buffers.
bool face_contact(const SatPolytope& ref, const Placement& ref_place, const SatPolytope& inc,
                  const Placement& inc_place, Index ref_face, bool ref_is_a, const Ties& ties, double max_separation,
                  CandidateList& out, int& clipped, const Vec* along) {
  const double tolerance = ties.length;
  const hull::HalfEdgeMesh& rm = *ref.mesh;
  const hull::HalfEdgeMesh& im = *inc.mesh;
  const hull::Plane& rp = ref.plane(ref_face);
  const Vec n = ref_place.direction(rp.normal);  // A's frame, out of ref
  const Vec u = along ? *along : n;              // the sweep
  const double slope = along ? n.dot(u) : 1.0;   // within the angle tolerance of 1
  const Vec ref_point = ref_place.point(ref.vertex(rm.origin(rm.faces[ref_face].edge)));
  const double offset = n.dot(ref_point);
  const Index inc_face = incident_face(inc, inc_place, u);
  if (inc_face == hull::kInvalidIndex) return false;
  const std::size_t inc_degree = im.face_degree(inc_face), ref_degree = rm.face_degree(ref_face);
  if (inc_degree + ref_degree > kClipCapacity) return false;

  std::array<Vec, kClipCapacity> buffer_a, buffer_b;
  std::array<Index, kClipCapacity> inc_edges;
  std::size_t count = 0;
  for (const Index e : im.face_edges(inc_face)) {
    inc_edges[count] = e;
    buffer_a[count++] = inc_place.point(inc.vertex(im.origin(e)));
  }
  const std::size_t inc_count = count;
  std::array<Vec, kClipCapacity> incident;  // the unclipped polygon, for the feature ids
  std::copy(buffer_a.begin(), buffer_a.begin() + inc_count, incident.begin());

  // Side planes of the reference face's edges, unit, outward (the face is
  // on the left of each half-edge); kept for the feature ids.
  UninitializedArray<hull::Plane, kClipCapacity> sides;
  std::array<Index, kClipCapacity> side_edges;
  std::size_t side_count = 0;
  for (const Index e : rm.face_edges(ref_face)) {
    const Vec p0 = ref_place.point(ref.vertex(rm.origin(e)));
    const Vec p1 = ref_place.point(ref.vertex(rm.destination(e)));
    const Vec side = (p1 - p0).cross(u).normalized();
    side_edges[side_count] = e;
    sides.set(side_count++, hull::Plane{side, side.dot(p0)});
  }
  Vec* src = buffer_a.data();
  Vec* dst = buffer_b.data();
  // A side plane with the whole incident polygon behind it (its bounding
  // ball, by half the tolerance: far beyond the plane's renormalisation in
  // clip_polygon) clips nothing: clip_polygon would copy the polygon
  // unchanged, in order, so it is skipped (a resting body smaller than the
  // face it rests on skips them all). The clipped polygon stays inside the
  // ball of the unclipped one.
  Vec centre = Vec::Zero();
  for (std::size_t i = 0; i < count; ++i) centre += src[i];
  centre /= static_cast<double>(std::max<std::size_t>(count, 1));
  double radius = 0.0;
  for (std::size_t i = 0; i < count; ++i) radius = std::max(radius, (src[i] - centre).squaredNorm());
  radius = std::sqrt(radius) * (1.0 + 1e-12);
  for (std::size_t k = 0; k < side_count && count > 0; ++k) {
    if (sides[k].signed_distance(centre) + radius <= 0.5 * tolerance) continue;
    const hull::ClipResult r = hull::clip_polygon(src, count, sides[k], dst, kClipCapacity, tolerance);
    if (r.status != hull::ClipStatus::ok) return false;
    count = r.count;
    std::swap(src, dst);
  }

  // Points within the contact distance, reduced to four here so that the
  // feature ids below are worked out for the kept points only.
  CandidateList below;
  clipped = static_cast<int>(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double s = (n.dot(src[i]) - offset) / slope;
    if (s <= max_separation) below.push(src[i], src[i], s, FeatureId{});
  }
  // Feature id: an incident vertex kept as is, else a crossing of an
  // incident edge with a side plane, else a corner of the reference face.
  const auto id_of = [&](const Vec& p, const Vec& on_ref) {
    FeatureId id;
    id.reference_on_b = !ref_is_a;
    id.reference = ref_face;
    for (std::size_t k = 0; k < inc_count; ++k)
      if (incident[k] == p) {
        id.kind = FeatureKind::face_vertex;
        id.incident = im.origin(inc_edges[k]);
        break;
      }
    if (id.kind == FeatureKind::none) {
      double best_side = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < side_count; ++k) {
        const double d = std::abs(sides[k].signed_distance(p));
        if (d < best_side) {
          best_side = d;
          id.clip = side_edges[k];
        }
      }
      double best_edge = std::numeric_limits<double>::infinity();
      Index edge = hull::kInvalidIndex;
      for (std::size_t k = 0; k < inc_count; ++k) {
        const Vec& a = incident[k];
        const Vec& b = incident[k + 1 == inc_count ? 0 : k + 1];
        const Vec ab = b - a;
        const double t = std::clamp(ab.dot(p - a) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
        const double d = (a + t * ab - p).norm();
        if (d < best_edge) {
          best_edge = d;
          edge = inc_edges[k];
        }
      }
      if (best_edge <= tolerance) {
        id.kind = FeatureKind::face_clip;
        id.incident = std::min(edge, im.twin(edge));
      } else {
        // A corner lies on two side planes and each side plane holds two
        // corners: "the nearest side plane" is rounding's choice and names
        // two corners alike. The corner is named by its own half-edge.
        id.kind = FeatureKind::face_corner;
        id.clip = corner_edge(ref, ref_place, ref_face, on_ref);
        id.incident = inc_face;
      }
    }
    return id;
  };
  std::array<std::size_t, kMaxContactPoints> keep{};
  int kept = reduce(below, u, ties, keep);
  // (hold 0, the default: the cold choice, as documented; no ids to match.)
  if (ties.last && ties.hold > 0.0 && below.size > static_cast<std::size_t>(kMaxContactPoints))
    kept = hold_last(below, u, ties, id_of, keep, kept);
  for (int i = 0; i < kept; ++i) {
    const Vec p = below[keep[i]].on_b;
    const double s = below[keep[i]].separation;
    const Vec on_ref = p - s * u;
    const FeatureId id = id_of(p, on_ref);
    if (ref_is_a)
      out.push(on_ref, p, s, id);
    else
      out.push(p, on_ref, s, id);
  }
  return true;
}

// Rounded shapes: the cores' face candidates (reference normal nf, A's
// frame, out of the reference) turned into witnesses on the rounded
// surfaces on the line through each point: the reference side moves out by
// its radius (nf is its face normal), the incident side by its exit
// distance along -nf, so each separation is the exact gap of the two
// rounded surfaces along nf there.
void round_candidates(CandidateList& c, const Vec& nf, bool ref_is_a, double r_ref, const SatPolytope& inc,
                      const Placement& inc_place, Index inc_face, double r_inc) {
  for (std::size_t i = 0; i < c.size; ++i) {
    Candidate& x = c[i];
    Vec& on_ref = ref_is_a ? x.on_a : x.on_b;
    Vec& on_inc = ref_is_a ? x.on_b : x.on_a;
    const double t = exit_distance(inc, inc_place, inc_face, on_inc, -nf, r_inc);
    on_ref += r_ref * nf;
    on_inc -= t * nf;
    x.separation -= r_ref + t;
  }
}

// The same along a normal `along` tilted off the reference face's normal
// (A's frame, out of the reference; the points from face_contact swept
// along it): the reference side moves by its exit along `along` from the
// reference core grown by r_ref (r_ref / cos of the tilt inside the face,
// less near its edges, exactly r_ref where `along` is in the core's normal
// cone), the incident side by its exit along -along.
void round_along(CandidateList& c, const Vec& along, bool ref_is_a, const SatPolytope& ref, const Placement& ref_place,
                 Index ref_face, double r_ref, const SatPolytope& inc, const Placement& inc_place, Index inc_face,
                 double r_inc) {
  for (std::size_t i = 0; i < c.size; ++i) {
    Candidate& x = c[i];
    Vec& on_ref = ref_is_a ? x.on_a : x.on_b;
    Vec& on_inc = ref_is_a ? x.on_b : x.on_a;
    const double t_ref = r_ref > 0.0 ? exit_distance(ref, ref_place, ref_face, on_ref, along, r_ref) : 0.0;
    const double t_inc = r_inc > 0.0 ? exit_distance(inc, inc_place, inc_face, on_inc, -along, r_inc) : 0.0;
    on_ref += t_ref * along;
    on_inc -= t_inc * along;
    x.separation -= t_ref + t_inc;
  }
}

// The face of `poly` whose normal is closest to n (searched around the
// support vertex in n), if within the angle tolerance (cosine cos_tol).
Index face_along(const SatPolytope& poly, const Vec& n, double cos_tol) {
  const Index v = poly.support(n);
  Index face = hull::kInvalidIndex;
  double best = cos_tol;
  for (const Index f : poly.mesh->vertex_faces(v)) {
    const double dot = poly.plane(f).normal.dot(n);
    if (dot >= best) {
      best = dot;
      face = f;
    }
  }
  return face;
}

// penetration()'s answer as a one-point contact (scale: the larger bounding radius).
ContactResult penetration_point(const PenetrationResult& p, double scale, const ContactSettings& settings) {
  ContactResult out;
  out.status = p.status;
  out.path = ContactPath::single_point;
  if (p.status == Status::degenerate || p.status == Status::invalid_input) return out;
  out.distance = p.distance;
  out.error_bound = p.error_bound;
  out.normal = p.normal;
  out.point_a = p.point_a;
  out.point_b = p.point_b;
  out.intersecting = p.distance <= 0.0;
  if (p.distance <= keep_below(settings, scale)) {
    out.count = 1;
    out.points[0].point = 0.5 * (p.point_a + p.point_b);
    out.points[0].depth = -p.distance;
    out.points[0].id.kind = FeatureKind::single;
  } else {
    out.path = ContactPath::separated;
  }
  return out;
}

// penetration()'s witnesses as one more candidate when every clipped point
// is shallower than they are by more than `slack` (1e-9 of the size). Its
// normal is exact only to about the square root of its distance's error
// (7e-6 rad seen: a side line over a face's edge, 0.05 apart), so B's line
// extreme along that normal can start beyond the swept side plane by that
// times the gap while the closest point lies on the plane: the clipping then
// cuts the line where its gap is larger, by the line's tilt times the part
// cut.
void add_witnesses_if_missed(const ContactResult& first, const WorldFrame& world, double slack, CandidateList& c) {
  for (std::size_t i = 0; i < c.size; ++i)
    if (c[i].separation <= first.distance + slack) return;
  FeatureId id;
  id.kind = FeatureKind::single;
  c.push(world.local(first.point_a), world.local(first.point_b), first.distance, id);
}

}  // namespace hedra::collision::detail::manifold
