// Contact manifolds (see manifold.hpp for the paths, the point convention and
// the feature ids). Everything below runs in A's core frame: B's geometry is
// placed there by the relative pose, and only the final points go to world.
#include <algorithm>
#include <cmath>
#include <hedra/collision/manifold.hpp>
#include <hedra/hull/assert.hpp>
#include <hedra/hull/mesh_edit.hpp>
#include <limits>
#include <new>
#include <type_traits>

#include "box_box.hpp"
#include "contact_choice.hpp"
#include "contact_depth.hpp"
#include "face_certificate.hpp"
#include "segment_box.hpp"

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

using Vec = Eigen::Vector3d;
using hull::Index;

// Clip buffers: an incident polygon of n vertices clipped by m side planes
// has at most n + m points; faces whose sum exceeds this take the single
// point path instead (no allocation, ever).
constexpr std::size_t kClipCapacity = 256;

// Fixed-capacity storage left uninitialised (types with default member
// initialisers would otherwise be written in full on every query: 8 kB of
// side planes cost a quarter of a box-box query).
template <class T, std::size_t N>
class UninitializedArray {
 public:
  UninitializedArray() {}
  static_assert(std::is_trivially_destructible_v<T>);
  T& operator[](std::size_t i) { return reinterpret_cast<T*>(storage_)[i]; }
  const T& operator[](std::size_t i) const { return reinterpret_cast<const T*>(storage_)[i]; }
  void set(std::size_t i, const T& value) { new (storage_ + i * sizeof(T)) T(value); }

 private:
  alignas(T) unsigned char storage_[sizeof(T) * N];
};

// A candidate contact point in A's core frame: its witnesses on the two
// cores and its separation along the normal (> 0: a gap).
struct Candidate {
  Vec on_a;
  Vec on_b;
  double separation;
  FeatureId id;
};

// Fixed capacity, left uninitialised until pushed (a few kB per query that
// default-initialising would write for nothing).
class CandidateList {
 public:
  CandidateList() {}
  std::size_t size = 0;
  Candidate& operator[](std::size_t i) { return data()[i]; }
  const Candidate& operator[](std::size_t i) const { return data()[i]; }
  void push(const Vec& on_a, const Vec& on_b, double separation, const FeatureId& id) {
    if (size < kClipCapacity) new (&data()[size++]) Candidate{on_a, on_b, separation, id};
  }

 private:
  static_assert(std::is_trivially_destructible_v<Candidate>);
  Candidate* data() { return reinterpret_cast<Candidate*>(storage_); }
  const Candidate* data() const { return reinterpret_cast<const Candidate*>(storage_); }
  alignas(Candidate) unsigned char storage_[sizeof(Candidate) * kClipCapacity];
};

// What counts as equal in the reduction: depths within `depth` (the
// touching band: equal to rounding), lengths within `length` (the geometric
// tolerance, as for the clipping).
struct Ties {
  double depth;
  double length;
  // Warm queries: the last frame's kept points (null: none) stay kept while
  // all are still candidates and their deepest is within `hold` of the
  // deepest candidate.
  const ContactCache* last = nullptr;
  double hold = 0.0;
};

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

// The frame of A's core in the world: x_world = R_a (offset_a + x) + t_a.
struct WorldFrame {
  const Pose& pose;
  Vec offset;
  Vec point(const Vec& x) const { return pose.rotation * (offset + x) + pose.translation; }
  Vec direction(const Vec& d) const { return pose.rotation * d; }
  Vec local(const Vec& x) const { return pose.rotation.transpose() * (x - pose.translation) - offset; }
};

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

// A placement of a polytope's frame in A's core frame: x -> R x + t
// (identity for A itself).
struct Placement {
  Eigen::Matrix3d rotation;
  Vec translation;
  Vec point(const Vec& x) const { return rotation * x + translation; }
  Vec direction(const Vec& d) const { return rotation * d; }
};

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

// Face contact: reference face `ref_face` of `ref`, incident face searched
// around inc's support vertex. Candidates' on_a / on_b follow A and B
// (ref_is_a says which is which). `along` (A's frame, out of ref, unit;
// null: the face's normal) is the direction the points are measured along:
// the side planes are swept along it, and each separation is the gap along
// it from the reference plane. Returns false when a face is too large for
// the fixed buffers.
bool face_contact(const SatPolytope& ref, const Placement& ref_place, const SatPolytope& inc,
                  const Placement& inc_place, Index ref_face, bool ref_is_a, const Ties& ties, double max_separation,
                  CandidateList& out, int& clipped, const Vec* along = nullptr) {
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

using detail::closest_segment_points;

template <class T>
constexpr bool is_polytope_v = std::is_same_v<T, Box> || std::is_same_v<T, Polyhedron>;

// A polytope's SAT view, or false when it has no solid (3D) hull.
bool polytope_view(const Box& box, BoxPolytopeStorage& storage, SatPolytope& out) {
  out = sat_polytope(box, storage);
  return true;
}
bool polytope_view(const Polyhedron& p, BoxPolytopeStorage&, SatPolytope& out) {
  if (p.hull->dimension() != 3) return false;
  out = sat_polytope(*p.hull);
  return true;
}

bool solid(const Box&) { return true; }
bool solid(const Polyhedron& p) { return p.hull->dimension() == 3; }

double scale_of(const SatPolytope& a, const SatPolytope& b) { return std::max(a.scale, b.scale); }

// Tolerance of the side-plane clipping and of "on a plane / on an edge"
// decisions: a point within it of a side plane counts as on it, so an
// incident vertex that a tilt of 1e-6 rad moves across the side plane of an
// equally wide reference face (stacked equal boxes) stays one vertex with one
// feature id instead of flipping between a vertex and a clipped point. The
// price: kept points may lie that far outside the reference face.
double geometric_tolerance(double scale) { return 1e-6 * scale; }

// The largest separation that still yields points: the contact distance
// plus the touching band of penetration() (a fraction of the pair's size).
// Touching surfaces are 0 apart only up to rounding: SAT's separation, a
// clipped point's, or penetration()'s distance of a pair placed exactly
// touching comes out +-1e-16 of the size, and a filter against the bare
// contact distance (0 by default) dropped every point of a resting body.
double keep_below(const ContactSettings& settings, double scale) {
  return settings.contact_distance + settings.penetration.touching_band * scale;
}

void flip(ContactResult& r) {
  r.normal = -r.normal;
  std::swap(r.point_a, r.point_b);
  for (int k = 0; k < r.count; ++k) r.points[k].id.reference_on_b = !r.points[k].id.reference_on_b;
}

ContactResult single_point(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, ContactCache* cache,
                           const ContactSettings& settings);
ContactResult penetration_point(const PenetrationResult& p, double scale, const ContactSettings& settings);

Index face_along(const SatPolytope& poly, const Vec& n, double cos_tol);

// A polytope pair as the manifold builder sees it, in A's core frame.
struct PolytopePair {
  SatPolytope pa, pb;
  RelativePose rel;
  double ra = 0.0, rb = 0.0;           // margins
  double scale = 0.0;                  // the pair's size
  double keep = 0.0;                   // largest separation that yields points (rounded surfaces)
  double band = 0.0;                   // penetration()'s touching band at the pair's size
  const ContactCache* last = nullptr;  // the last frame's kept points (warm queries)
  double hold = 0.0;                   // how far they may be shallower (ContactSettings::hold)
  double core_contact = 0.0;           // the same between the cores
  double shape_scale = 0.0;            // max bounding radius, as single_point measures it
  Placement identity{Eigen::Matrix3d::Identity(), Vec::Zero()};
  Placement placed_b;
};

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

void add_witnesses_if_missed(const ContactResult& first, const WorldFrame& world, double slack, CandidateList& c);

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
ContactResult build_manifold(const Shape& shape_a, const Pose& pose_a, const Shape& shape_b, const Pose& pose_b,
                             const PolytopePair& pp, const WorldFrame& world, const SatAxis& best,
                             const ContactResult* exact, ContactCache* cache, const ContactSettings& settings,
                             const ContactStats& stats, double exact_limit) {
  const auto fallback = [&] {
    ContactResult single = exact ? *exact : single_point(shape_a, pose_a, shape_b, pose_b, cache, settings);
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
    const ContactResult r = rounded_cores_apart(pp, pose_a, world, fallback(), stats, settings, used);
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
  if (detail::deepest_short_of_axis(deepest, axis_separation, exact_limit - (shifted ? ra + rb : 0.0), pp.band,
                                    held)) {
    SatAxis used;
    const ContactResult r = rounded_cores_apart(pp, pose_a, world, fallback(), stats, settings, used);
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
ContactResult build_chosen(const Shape& shape_a, const Pose& pose_a, const Shape& shape_b, const Pose& pose_b,
                           const PolytopePair& pp, const WorldFrame& world, const AxisCandidates& c,
                           const ContactResult* exact, ContactCache* cache, const ContactSettings& settings,
                           const ContactStats& stats, double exact_limit) {
  const SatAxis best = choose_axis(c, cache, settings, pp.scale);
  remember(cache, best);
  ContactResult r =
      build_manifold(shape_a, pose_a, shape_b, pose_b, pp, world, best, exact, cache, settings, stats, exact_limit);
  const SatAxis cold = choose_axis(c, nullptr, settings, pp.scale);
  if (r.path != ContactPath::single_point || cold.kind == best.kind) return r;
  remember(cache, cold);
  return build_manifold(shape_a, pose_a, shape_b, pose_b, pp, world, cold, exact, cache, settings, stats, exact_limit);
}

// SAT's axes: the full separating-axis test (sat.hpp).
ContactResult contact_by_sat(const Shape& shape_a, const Pose& pose_a, const Shape& shape_b, const Pose& pose_b,
                             const PolytopePair& pp, const WorldFrame& world, ContactCache* cache,
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
    const ContactResult single = single_point(shape_a, pose_a, shape_b, pose_b, cache, settings);
    SatAxis used;
    const ContactResult r = rounded_cores_apart(pp, pose_a, world, single, stats, settings, used);
    remember(cache, used);
    return r;
  }
  // Overlapping or touching cores: SAT's largest separation is exact.
  const double largest = std::max({s.face_a.separation, s.face_b.separation, s.edge.separation});
  const double band = settings.penetration.touching_band * pp.scale;
  const double limit = largest <= band ? largest + band : std::numeric_limits<double>::infinity();
  ContactResult r = build_chosen(shape_a, pose_a, shape_b, pose_b, pp, world, c, nullptr, cache, settings, stats, limit);
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
ContactResult contact_by_normal(const Shape& shape_a, const Pose& pose_a, const Shape& shape_b, const Pose& pose_b,
                                const PolytopePair& pp, const WorldFrame& world, ContactCache* cache,
                                const ContactSettings& settings) {
  const PenetrationResult p =
      penetration(shape_a, pose_a, shape_b, pose_b, cache ? &cache->gjk : nullptr, settings.penetration);
  const ContactResult exact = penetration_point(p, pp.shape_scale, settings);
  if (p.status == Status::degenerate || p.status == Status::invalid_input) return exact;
  const Vec n = pose_a.rotation.transpose() * p.normal;  // A's core frame, A -> B
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
    const ContactResult r = rounded_cores_apart(pp, pose_a, world, exact, ContactStats{}, settings, used);
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
  ContactResult r =
      build_chosen(shape_a, pose_a, shape_b, pose_b, pp, world, c, &exact, cache, settings, ContactStats{}, limit);
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
bool answer_from_cache(const Shape& shape_a, const Pose& pose_a, const Shape& shape_b, const Pose& pose_b,
                       const PolytopePair& pp, const WorldFrame& world, ContactCache* cache,
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
    out = build_manifold(shape_a, pose_a, shape_b, pose_b, pp, world, axis, nullptr, cache, settings, hit,
                         axis.separation + tol + band);
    // Certified: the cores' exact separation lies in [s, s + tol].
    out.error_bound =
        detail::bound_within(out.distance, out.error_bound, axis.separation + 0.5 * tol - pp.ra - pp.rb, 0.5 * tol);
    return true;
  }
  const AxisCandidates c{face_near(pp, axis.normal, true), face_near(pp, axis.normal, false), axis};
  out = build_chosen(shape_a, pose_a, shape_b, pose_b, pp, world, c, nullptr, cache, settings, hit,
                     axis.separation + 2.0 * band);
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

template <class SA, class SB>
ContactResult polytope_contact(const Shape& shape_a, const SA& a, const Pose& pose_a, const Shape& shape_b, const SB& b,
                               const Pose& pose_b, ContactCache* cache, const ContactSettings& settings) {
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
  pp.shape_scale = std::max(bounding_radius(shape_a), bounding_radius(shape_b));
  const WorldFrame world{pose_a, core_offset(a)};
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
  if (answer_from_cache(shape_a, pose_a, shape_b, pose_b, pp, world, cache, settings, warm)) return stored(warm);
  if (use_sat(pp, settings))
    return stored(contact_by_sat(shape_a, pose_a, shape_b, pose_b, pp, world, cache, settings));
  return stored(contact_by_normal(shape_a, pose_a, shape_b, pose_b, pp, world, cache, settings));
}

// ---- curved shapes against a polytope -------------------------------------

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

// The side plane of half-edge e of a face of `poly` swept along n (A's frame,
// within the angle tolerance of the face's normal), outward: a point lies
// inside every swept side plane when its projection along n onto the face's
// plane lies inside the face.
Vec swept_side(const SatPolytope& poly, Index e, const Vec& n) {
  const hull::HalfEdgeMesh& m = *poly.mesh;
  return (poly.vertex(m.destination(e)) - poly.vertex(m.origin(e))).cross(n);
}

// A point x of B's core against the plane of a face of A along the normal n:
// its foot on the plane along n, and its separation along n.
void push_along(const hull::Plane& plane, const Vec& n, const Vec& x, const FeatureId& id, CandidateList& out) {
  const double s = plane.signed_distance(x) / plane.normal.dot(n);
  out.push(x - s * n, x, s, id);
}

// Segment s0-s1 (A's frame, on B's core) clipped by the side planes of face f
// swept along the normal n.
bool segment_on_face(const SatPolytope& poly, Index f, const Vec& n, const Vec& s0, const Vec& s1, double tol,
                     CandidateList& out) {
  const hull::HalfEdgeMesh& m = *poly.mesh;
  std::array<Vec, 4> buf_a{s0, s1}, buf_b;
  Vec* src = buf_a.data();
  Vec* dst = buf_b.data();
  std::size_t count = 2;
  for (const Index e : m.face_edges(f)) {
    const Vec side = swept_side(poly, e, n);
    const hull::ClipResult r =
        hull::clip_polygon(src, count, {side, side.dot(poly.vertex(m.origin(e)))}, dst, buf_b.size(), tol);
    if (r.status != hull::ClipStatus::ok) return false;
    count = r.count;
    std::swap(src, dst);
    if (count == 0) break;
  }
  for (std::size_t i = 0; i < count; ++i) {
    const Vec& p = src[i];
    FeatureId id;
    id.kind = FeatureKind::segment;
    id.reference = f;
    if (p == s0) {
      id.incident = 0;
    } else if (p == s1) {
      id.incident = 1;
    } else {
      double best = std::numeric_limits<double>::infinity();
      for (const Index e : m.face_edges(f)) {
        const double d = std::abs(swept_side(poly, e, n).normalized().dot(p - poly.vertex(m.origin(e))));
        if (d < best) {
          best = d;
          id.clip = e;
        }
      }
      id.incident = 2;
    }
    push_along(poly.plane(f), n, p, id, out);
  }
  return true;
}

// Cap disc (centre c, outward unit normal cn, radius r, local axes ux, uy in
// A's frame) against face f of `poly` along the normal n; see manifold.hpp.
// A point's separation along n is affine over the cap's plane, so its
// extremes over the region (disc x face projected along n) are among the
// candidates: the rim point deepest toward the face's plane, the projected
// face vertices inside the disc, and the edges' crossings of the rim.
void cap_on_face(const SatPolytope& poly, Index f, const Vec& n, const Vec& c, const Vec& cn, double r, const Vec& ux,
                 const Vec& uy, double tol, CandidateList& out) {
  const hull::HalfEdgeMesh& m = *poly.mesh;
  const hull::Plane& plane = poly.plane(f);
  const Vec& nf = plane.normal;
  auto inside_face = [&](const Vec& x) {
    for (const Index e : m.face_edges(f)) {
      const Vec side = swept_side(poly, e, n);
      if (side.dot(x - poly.vertex(m.origin(e))) > tol * side.norm()) return false;
    }
    return true;
  };
  auto add = [&](const Vec& x, std::uint32_t which) {
    FeatureId id;
    id.kind = FeatureKind::cap;
    id.reference = f;
    id.incident = which;
    push_along(plane, n, x, id, out);
  };
  const Vec rims[4] = {ux, -ux, uy, -uy};
  for (std::uint32_t k = 0; k < 4; ++k)
    if (inside_face(c + r * rims[k])) add(c + r * rims[k], k);
  // The deepest rim point: towards -nf within the cap plane.
  const Vec w = -(nf - nf.dot(cn) * cn);
  const double wn = w.norm();
  if (wn > 1e-12 && inside_face(c + (r / wn) * w)) add(c + (r / wn) * w, 4);
  // Project the polygon onto the cap plane along n: p -> p - ((p - c).cn / n.cn) n.
  const double ncn = n.dot(cn);  // close to -1 here
  auto project = [&](const Vec& p) { return Vec(p - ((p - c).dot(cn) / ncn) * n); };
  const double r2 = r * r;
  for (const Index e : m.face_edges(f)) {
    const Vec q0 = project(poly.vertex(m.origin(e)));
    const Vec q1 = project(poly.vertex(m.destination(e)));
    if ((q0 - c).squaredNorm() <= r2) add(q0, 8 + m.origin(e));
    // |q0 + s dq - c|^2 = r^2 for s in (0, 1): the edge crossing the rim.
    const Vec dq = q1 - q0, rel = q0 - c;
    const double qa = dq.squaredNorm(), qb = dq.dot(rel), qc = rel.squaredNorm() - r2;
    const double disc = qb * qb - qa * qc;
    if (!(qa > 0.0) || !(disc >= 0.0)) continue;
    const double root = std::sqrt(disc);
    const double roots[2] = {(-qb - root) / qa, (-qb + root) / qa};
    for (int k = 0; k < 2; ++k)
      if (roots[k] > 0.0 && roots[k] < 1.0) add(q0 + roots[k] * dq, (1u << 20) + 2 * e + static_cast<std::uint32_t>(k));
  }
}

// The world result from penetration(): one point.
ContactResult single_point(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, ContactCache* cache,
                           const ContactSettings& settings) {
  const PenetrationResult p = penetration(a, pose_a, b, pose_b, cache ? &cache->gjk : nullptr, settings.penetration);
  return penetration_point(p, std::max(bounding_radius(a), bounding_radius(b)), settings);
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

// Distance from a point (B's local frame) to a cylinder's or cone's core,
// from the meridian half-section (radial >= 0, axial): the nearest of its
// edges; `away` is the unit direction from the closest point (local frame).
// For points outside the core (0 and an arbitrary `away` inside).
template <class SB>
double core_distance(const SB& b, const Vec& p, Vec& away) {
  const double h = b.half_length, r = b.radius;
  const double radial = std::hypot(p.x(), p.y());
  const Eigen::Vector2d q(radial, p.z());
  const bool cylinder = std::is_same_v<SB, Cylinder>;
  // Base centre, rim, top rim (cylinder) or apex (cone), top centre.
  const Eigen::Vector2d corners[4] = {{0.0, -h}, {r, -h}, {cylinder ? r : 0.0, h}, {0.0, h}};
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d closest = q;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d e = corners[k + 1] - corners[k];
    const double len2 = e.squaredNorm();
    const double t = len2 > 0.0 ? std::clamp((q - corners[k]).dot(e) / len2, 0.0, 1.0) : 0.0;
    const Eigen::Vector2d c = corners[k] + t * e;
    const double d = (q - c).norm();
    if (d < best) {
      best = d;
      closest = c;
    }
  }
  const Eigen::Vector2d w = best > 0.0 ? Eigen::Vector2d((q - closest) / best) : Eigen::Vector2d(0.0, 1.0);
  const Vec radial_unit = radial > 0.0 ? Vec(p.x() / radial, p.y() / radial, 0.0) : Vec::UnitX();
  away = w.x() * radial_unit + Vec(0.0, 0.0, w.y());
  return best;
}

// How far the ray x + s d (A's frame; x on B's core, d unit and leaving the
// core there) runs inside B's core grown by r: the root of
// distance(x + s d) = r, between r (the distance grows at most as fast as
// s) and 2 r (at least as fast as s |d . normal| > 1/2 near a face's normal).
// The distance along a line is convex, so Newton's steps from 2 r decrease
// monotonically onto the root: 3 to 4 steps to rounding (at most 16).
template <class SB>
double rounded_exit(const SB& b, const RelativePose& rel, const Vec& x, const Vec& d, double r) {
  const Vec p = rel.rotation.transpose() * (x - rel.translation), dl = rel.rotation.transpose() * d;
  double s = 2.0 * r;
  for (int i = 0; i < 16; ++i) {
    Vec away;
    const double g = core_distance(b, p + s * dl, away) - r;
    const double slope = away.dot(dl);
    if (!(slope > 0.0)) break;
    const double step = g / slope;
    s -= step;
    if (!(std::abs(step) > 4.0 * std::numeric_limits<double>::epsilon() * s)) break;
  }
  return std::clamp(s, r, 2.0 * r);
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

// The candidates of B's cap or straight side line lying on face f of A along
// the normal n (A's frame, A -> B, within the angle tolerance of the face's
// normal nf), see manifold.hpp; ContactPath::none when neither lies along
// the face (or the clipping failed).
template <class SB>
ContactPath curved_candidates(const SatPolytope& pa, Index f, const Vec& n, const SB& b, const RelativePose& rel,
                              const ContactSettings& settings, double tol, CandidateList& candidates) {
  const Vec& nf = pa.plane(f).normal;
  const Vec axis = rel.rotation.col(2);  // B's z in A's frame
  const Vec centre = rel.translation;
  const double h = b.half_length;
  if constexpr (std::is_same_v<SB, Capsule>) {
    if (!segment_on_face(pa, f, n, centre - h * axis, centre + h * axis, tol, candidates)) return ContactPath::none;
    return ContactPath::segment;
  } else {
    // Cylinder: caps at +-h; cone: the base at -h only.
    const double cos_tol = std::cos(settings.face_angle_tolerance);
    const double an = axis.dot(nf);
    const bool cylinder = std::is_same_v<SB, Cylinder>;
    const bool cap_down = an >= cos_tol;             // the cap at -h faces A
    const bool cap_up = cylinder && -an >= cos_tol;  // the cap at +h faces A
    if (cap_down || cap_up) {
      const Vec cn = cap_up ? axis : Vec(-axis);
      cap_on_face(pa, f, n, centre + h * cn, cn, b.radius, rel.rotation.col(0), rel.rotation.col(1), tol, candidates);
      return ContactPath::cap;
    }
    // The side's straight line extreme along -n (radial -n): from the base
    // rim (a cylinder's and a cone's alike) to the top rim (cylinder) or the
    // apex (cone).
    Vec u = -(n - n.dot(axis) * axis);
    const double un = u.norm();
    if (!(un > 0.0)) return ContactPath::none;
    u /= un;
    const Vec s0 = centre - h * axis + b.radius * u;
    const Vec s1 = cylinder ? Vec(centre + h * axis + b.radius * u) : Vec(centre + h * axis);
    const Vec g = s1 - s0;
    if (!(std::abs(g.dot(nf)) <= std::sin(settings.face_angle_tolerance) * g.norm())) return ContactPath::none;
    if (!segment_on_face(pa, f, n, s0, s1, tol, candidates)) return ContactPath::none;
    return ContactPath::segment;
  }
}

// penetration()'s point for the pair; for a box against a capsule whose
// segment misses the box's core by more than the touching band, the same
// point in closed form (segment_box.hpp: the closest points of the segment
// and the box, exact where GJK iterates to its tolerance), the capsule's
// radius and the box's margin taken off along their normal.
template <class SA, class SB>
ContactResult curved_first_point(const Shape& shape_a, const SA& a, const Pose& pose_a, const Shape& shape_b,
                                 const SB& b, const Pose& pose_b, ContactCache* cache,
                                 const ContactSettings& settings) {
  if constexpr (std::is_same_v<SA, Box> && std::is_same_v<SB, Capsule>) {
    const RelativePose rel = relative_pose(pose_a, core_offset(a), pose_b, core_offset(b));
    const Vec axis = rel.rotation.col(2);
    const double scale = std::max(bounding_radius(shape_a), bounding_radius(shape_b));
    detail::SegmentBoxClosest c;
    if (detail::segment_box_closest(rel.translation - b.half_length * axis, rel.translation + b.half_length * axis,
                                    a.half_extents, settings.penetration.touching_band * scale, c)) {
      const WorldFrame world{pose_a, core_offset(a)};
      const Vec n = (c.on_segment - c.on_box) / c.distance;
      HEDRA_ASSERT(std::abs(n.squaredNorm() - 1.0) <= 1e-12);
      PenetrationResult p;
      p.distance = c.distance - core_radius(a) - core_radius(b);
      p.intersecting = p.distance <= 0.0;
      p.normal = world.direction(n);
      p.point_a = world.point(c.on_box + core_radius(a) * n);
      p.point_b = world.point(c.on_segment - core_radius(b) * n);
      return penetration_point(p, scale, settings);
    }
  }
  return single_point(shape_a, pose_a, shape_b, pose_b, cache, settings);
}

// A polytope A against a capsule, cylinder or cone B. The manifold is built
// around penetration()'s normal n: the face of A within the angle
// tolerance of n is the reference, and B's cap or side line is clipped by
// that face's side planes swept along n (not along the face's normal: where
// the closest or deepest features are the face's edge and a part of B
// hanging over it, n is tilted and that part lies beyond the face's side
// plane but inside the swept one), so each point's separation is its gap
// along n and the deepest point is penetration()'s (its witnesses added
// where n's own error still cuts them away).
template <class SA, class SB>
ContactResult curved_contact(const Shape& shape_a, const SA& a, const Pose& pose_a, const Shape& shape_b, const SB& b,
                             const Pose& pose_b, ContactCache* cache, const ContactSettings& settings) {
  ContactResult first = curved_first_point(shape_a, a, pose_a, shape_b, b, pose_b, cache, settings);
  if (first.count == 0 || first.status != Status::ok) return first;
  BoxPolytopeStorage storage;
  SatPolytope pa;
  if (!polytope_view(a, storage, pa)) return first;
  const RelativePose rel = relative_pose(pose_a, core_offset(a), pose_b, core_offset(b));
  const double ra = core_radius(a), rb = core_radius(b);
  const WorldFrame world{pose_a, core_offset(a)};
  const Vec n = pose_a.rotation.transpose() * first.normal;  // A's frame, A -> B
  const Index f = face_along(pa, n, std::cos(settings.face_angle_tolerance));
  if (f == hull::kInvalidIndex) return first;
  const double scale = std::max(pa.scale, bounding_radius(b));
  const double tol = geometric_tolerance(scale);
  CandidateList candidates;
  ContactResult out;
  out.stats = first.stats;
  out.path = curved_candidates(pa, f, n, b, rel, settings, tol, candidates);
  if (out.path == ContactPath::none) return first;
  out.stats.clipped_points = static_cast<int>(candidates.size);
  // Rounded surfaces: A's side where the line along n leaves A's core grown
  // by ra (ra / cos of the tilt off the face, less near its edges). A
  // capsule is round about its segment: each point's exit along -n from the
  // segment (r / sin of the tilt on the side, less near an end), not the
  // radius. A capsule standing on the face, tilted so little that the line
  // through its upper end passes through the lower end's ball (2 half_length
  // sin(tilt) < r), has both lines leave it through that ball: one ball
  // against a face touches at one point, so of the points on one end's ball
  // only the deepest (penetration()'s, the ball's lowest) stays; a capsule
  // lying on the face keeps its two ends (on different balls, or the side).
  // Cylinders and cones: where the line along -n leaves the core grown by rb
  // (rb / cos of its angle to the core's normal there, less near a rim).
  const Placement identity{Eigen::Matrix3d::Identity(), Vec::Zero()};
  const Vec axis = rel.rotation.col(2);
  const Vec s0 = rel.translation - b.half_length * axis, s1 = rel.translation + b.half_length * axis;
  // The end ball a capsule's witness lies on (beyond that end along the
  // axis), or -1 (the side; cylinders and cones).
  const auto end_ball = [&](const Vec& on_b) {
    if constexpr (std::is_same_v<SB, Capsule>) {
      const Vec d = s1 - s0;
      if ((on_b - s0).dot(-d) > tol * d.norm()) return 0;
      if ((on_b - s1).dot(d) > tol * d.norm()) return 1;
    }
    return -1;
  };
  std::array<int, kClipCapacity> balls;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < candidates.size; ++i) {
    Candidate x = candidates[i];
    const double ta = ra > 0.0 ? exit_distance(pa, identity, f, x.on_a, n, ra) : 0.0;
    double tb = 0.0;
    if constexpr (std::is_same_v<SB, Capsule>)
      tb = std::max(segment_exit(x.on_b, -n, s0, s1, rb), segment_exit(x.on_b, -n, s1, s0, rb));
    else if (rb > 0.0)
      tb = rounded_exit(b, rel, x.on_b, -n, rb);
    x.on_a += ta * n;
    x.on_b -= tb * n;
    x.separation -= ta + tb;
    // The same point, or the same end ball: the deeper stays.
    const int ball = end_ball(x.on_b);
    std::size_t same = kept;
    for (std::size_t k = 0; k < kept && same == kept; ++k)
      if ((candidates[k].on_b - x.on_b).norm() <= tol || (ball >= 0 && balls[k] == ball)) same = k;
    if (same < kept) {
      if (x.separation < candidates[same].separation) candidates[same] = x;
      continue;
    }
    balls[kept] = ball;
    candidates[kept++] = x;
  }
  candidates.size = kept;
  add_witnesses_if_missed(first, world, settings.penetration.touching_band * scale, candidates);
  const Ties ties{settings.penetration.touching_band * scale, tol};
  emit(candidates, n, 0.0, 0.0, keep_below(settings, scale + std::max(ra, rb)), ties, world, out);
  if (out.count == 0) return first;
  out.error_bound = detail::bound_within(out.distance, out.error_bound, first.distance, first.error_bound);
  return out;
}

template <class SA, class SB>
ContactResult contact_typed(const Shape& shape_a, const SA& a, const Pose& pose_a, const Shape& shape_b, const SB& b,
                            const Pose& pose_b, ContactCache* cache, const ContactSettings& settings) {
  constexpr bool curved_a = std::is_same_v<SA, Capsule> || std::is_same_v<SA, Cylinder> || std::is_same_v<SA, Cone>;
  constexpr bool curved_b = std::is_same_v<SB, Capsule> || std::is_same_v<SB, Cylinder> || std::is_same_v<SB, Cone>;
  if constexpr (std::is_same_v<SA, Box> && std::is_same_v<SB, Box>) {
    ContactResult r;  // box_box.cpp; what it hands back, the general path answers
    if (detail::box_box_contact(a, pose_a, b, pose_b, cache, settings, r)) return r;
  } else if (cache) {
    cache->box.valid = false;  // the box memory is for box pairs only
  }
  if constexpr (is_polytope_v<SA> && is_polytope_v<SB>) {
    if (!solid(a) || !solid(b)) return single_point(shape_a, pose_a, shape_b, pose_b, cache, settings);
    return polytope_contact(shape_a, a, pose_a, shape_b, b, pose_b, cache, settings);
  } else if constexpr (is_polytope_v<SA> && curved_b) {
    return curved_contact(shape_a, a, pose_a, shape_b, b, pose_b, cache, settings);
  } else if constexpr (curved_a && is_polytope_v<SB>) {
    ContactResult r = curved_contact(shape_b, b, pose_b, shape_a, a, pose_a, cache, settings);
    flip(r);
    return r;
  } else {
    return single_point(shape_a, pose_a, shape_b, pose_b, cache, settings);
  }
}

}  // namespace

ContactResult contact(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, ContactCache* cache,
                      const ContactSettings& settings) {
  // valid(), not only finite(): translations beyond max_coordinate are invalid in
  // every query.
  // is_valid(): validate()'s predicate without building its message.
  if (!pose_a.valid() || !pose_b.valid() || !is_valid(a) || !is_valid(b) || !pair_in_range(a, pose_a, b, pose_b) ||
      !std::isfinite(settings.contact_distance)) {
    ContactResult out;
    out.status = Status::invalid_input;
    return out;
  }
  return std::visit(
      [&](const auto& sa, const auto& sb) {
        ContactResult r = contact_typed(a, sa, pose_a, b, sb, pose_b, cache, settings);
        if (r.status == Status::invalid_input || r.status == Status::degenerate)
          r.error_bound = std::numeric_limits<double>::infinity();
        else if (std::isfinite(r.error_bound))
          r.error_bound += detail::contact_rounding(detail::rough_size(sa) + detail::rough_size(sb),
                                                    pose_b.translation - pose_a.translation);
        HEDRA_ASSERT(r.error_bound >= 0.0);  // manifold.hpp: a bound, never NaN
        return r;
      },
      a, b);
}

}  // namespace hedra::collision
