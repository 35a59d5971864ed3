// Editing operations on a HalfEdgeMesh (see mesh_edit.hpp for the contracts).
//
// split_edge / split_face rewire a constant number of links and append the
// new elements, so every existing index stays valid.
//
// cut_by_plane never edits the input in place: PlaneCut decides everything
// first (vertex classes, crossing points, kept polygons, the border loop) into
// scratch arrays, builds the result into a fresh mesh, and cut_by_plane swaps
// it in only when the border was one simple loop (or, for a flat mesh, pairs
// of opposite half-edges). Why the result's links, manifold vertices and
// geometry hold: docs/design.md (hull). Debug builds assert the links after
// every edit whose input links agreed.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <hedra/hull/assert.hpp>
#include <hedra/hull/mesh_edit.hpp>
#include <limits>
#include <utility>

namespace hedra::hull {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// The same scale as HalfEdgeMesh::from_polygons: a few dozen units of
// rounding of the largest coordinate.
double extent_tolerance(double extent) { return 48.0 * kEps * std::max(extent, std::numeric_limits<double>::min()); }

double mesh_tolerance(const HalfEdgeMesh& mesh) {
  const double t = mesh.tolerance();
  if (t > 0 && std::isfinite(t)) return t;
  double extent = 0;
  for (const auto& v : mesh.vertices) extent = std::max(extent, v.position.cwiseAbs().maxCoeff());
  return extent_tolerance(extent);
}

// Normalises a plane; false when it has no direction or is not finite.
bool normalized_plane(const Plane& in, Plane& out) {
  if (!in.normal.allFinite() || !std::isfinite(in.offset)) return false;
  const double len = in.normal.norm();
  if (!(len > 0) || !std::isfinite(len)) return false;
  out.normal = in.normal / len;
  out.offset = in.offset / len;
  return out.normal.allFinite() && std::isfinite(out.offset);
}

// The point where segment b -> f crosses the plane, computed from the end
// strictly behind (d_b < 0 < d_f) so that t = d_b / (d_b - d_f) lies in
// (0, 1) and the division cannot be by zero.
Eigen::Vector3d crossing_point(const Eigen::Vector3d& b, double d_b, const Eigen::Vector3d& f, double d_f) {
  const double t = d_b / (d_b - d_f);
  return b + t * (f - b);
}

enum class Side : unsigned char { behind, on, front };

Side classify(double d, double tol) { return d > tol ? Side::front : (d < -tol ? Side::behind : Side::on); }

// The link invariants of half_edge_mesh.hpp at half-edge e, range-checked:
// what every edit must keep. Debug builds check them where an edit rewired.
[[maybe_unused]] bool links_agree(const HalfEdgeMesh& m, Index e) {
  const std::size_t H = m.edges.size();
  if (e >= H) return false;
  const HalfEdge& h = m.edges[e];
  if (h.twin >= H || h.next >= H || h.prev >= H || h.twin == e) return false;
  return m.edges[h.twin].twin == e && m.edges[h.prev].next == e && m.edges[h.next].prev == e &&
         m.edges[h.next].face == h.face && m.edges[h.next].origin == m.edges[h.twin].origin;
}

[[maybe_unused]] bool all_links_agree(const HalfEdgeMesh& m) {
  for (Index e = 0; e < m.edges.size(); ++e)
    if (!links_agree(m, e)) return false;
  return true;
}

// links_agree on every half-edge of face f's cycle, each naming f.
[[maybe_unused]] bool face_links_agree(const HalfEdgeMesh& m, Index f) {
  const Index start = m.faces[f].edge;
  Index e = start;
  std::size_t n = 0;
  do {
    if (!links_agree(m, e) || m.edges[e].face != f) return false;
    e = m.edges[e].next;
  } while (e != start && ++n <= m.edges.size());
  return e == start;
}

}  // namespace

// ---------------------------------------------------------------------------
// split_edge

Index split_edge(HalfEdgeMesh& mesh, Index e, const Eigen::Vector3d& point) {
  if (e >= mesh.edges.size() || !point.allFinite()) return kInvalidIndex;
  const Index t = mesh.edges[e].twin;
  if (t >= mesh.edges.size()) return kInvalidIndex;
  const Index m = static_cast<Index>(mesh.vertices.size());
  const Index e2 = static_cast<Index>(mesh.edges.size());  // m -> b, in face(e)
  const Index t2 = e2 + 1;                                 // m -> a, in face(t)
  const Index e_next = mesh.edges[e].next;
  const Index t_next = mesh.edges[t].next;
#if HEDRA_ASSERTS_ENABLED
  const bool consistent =
      links_agree(mesh, e) && links_agree(mesh, t) && links_agree(mesh, e_next) && links_agree(mesh, t_next);
#endif

  HalfEdge he2;
  he2.origin = m;
  he2.twin = t;
  he2.next = e_next;
  he2.prev = e;
  he2.face = mesh.edges[e].face;
  HalfEdge ht2;
  ht2.origin = m;
  ht2.twin = e;
  ht2.next = t_next;
  ht2.prev = t;
  ht2.face = mesh.edges[t].face;
  mesh.edges.push_back(he2);
  mesh.edges.push_back(ht2);
  mesh.vertices.push_back({point, e2});

  // e: a -> m, twin m -> a; t: b -> m, twin m -> b. Origins of e and t, and so
  // every vertex's outgoing link, are unchanged.
  mesh.edges[e].next = e2;
  mesh.edges[e].twin = t2;
  mesh.edges[t].next = t2;
  mesh.edges[t].twin = e2;
  mesh.edges[e_next].prev = e2;
  mesh.edges[t_next].prev = t2;
  // Links that agreed around the edge still agree, new half-edges included.
  HEDRA_ASSERT(!consistent || (links_agree(mesh, e) && links_agree(mesh, t) && links_agree(mesh, e2) &&
                               links_agree(mesh, t2) && links_agree(mesh, e_next) && links_agree(mesh, t_next)));
  return m;
}

// ---------------------------------------------------------------------------
// split_face

Index split_face(HalfEdgeMesh& mesh, Index f, Index v_a, Index v_b) {
  if (f >= mesh.faces.size() || v_a == v_b) return kInvalidIndex;
  const std::size_t cap = mesh.edges.size();
  const Index start = mesh.faces[f].edge;
  if (start >= cap) return kInvalidIndex;
  // Find the half-edges of f leaving v_a and v_b (the walk is capped by the
  // number of half-edges, so a corrupt cycle cannot loop forever).
  Index ea = kInvalidIndex, eb = kInvalidIndex;
  std::size_t degree = 0;
  Index e = start;
  do {
    if (mesh.edges[e].origin == v_a) ea = e;
    if (mesh.edges[e].origin == v_b) eb = e;
    e = mesh.edges[e].next;
    ++degree;
  } while (e != start && degree <= cap);
  if (e != start || ea == kInvalidIndex || eb == kInvalidIndex) return kInvalidIndex;
  if (mesh.edges[ea].next == eb || mesh.edges[eb].next == ea) return kInvalidIndex;  // adjacent: not a diagonal

  // Both parts must have area: some vertex of each, strictly between v_a and
  // v_b, more than tolerance off the diagonal's line. Without it a part would
  // be a sliver face with no well-defined plane or winding.
  const double tol = mesh_tolerance(mesh);
  const Eigen::Vector3d pa = mesh.position(v_a);
  const Eigen::Vector3d axis = mesh.position(v_b) - pa;
  const double axis_len = axis.norm();
  if (!(axis_len > tol)) return kInvalidIndex;
  const Eigen::Vector3d dir = axis / axis_len;
  auto part_has_area = [&](Index from, Index to) {
    std::size_t n = 0;
    for (Index h = mesh.edges[from].next; h != to && n <= cap; h = mesh.edges[h].next, ++n) {
      const Eigen::Vector3d r = mesh.position(mesh.edges[h].origin) - pa;
      if ((r - r.dot(dir) * dir).norm() > tol) return true;
    }
    return false;
  };
  if (!part_has_area(ea, eb) || !part_has_area(eb, ea)) return kInvalidIndex;

#if HEDRA_ASSERTS_ENABLED
  const bool consistent = face_links_agree(mesh, f);
#endif
  const Index pb = mesh.edges[eb].prev;       // ends at v_b
  const Index pa_edge = mesh.edges[ea].prev;  // ends at v_a
  const Index g = static_cast<Index>(mesh.faces.size());
  const Index d1 = static_cast<Index>(mesh.edges.size());  // v_a -> v_b, in g
  const Index d2 = d1 + 1;                                 // v_b -> v_a, in f

  HalfEdge h1;
  h1.origin = v_a;
  h1.twin = d2;
  h1.prev = pa_edge;
  h1.next = eb;
  h1.face = g;
  HalfEdge h2;
  h2.origin = v_b;
  h2.twin = d1;
  h2.prev = pb;
  h2.next = ea;
  h2.face = f;
  mesh.edges.push_back(h1);
  mesh.edges.push_back(h2);
  mesh.edges[pa_edge].next = d1;
  mesh.edges[eb].prev = d1;
  mesh.edges[pb].next = d2;
  mesh.edges[ea].prev = d2;

  Face face_g;
  face_g.edge = eb;
  face_g.plane = mesh.faces[f].plane;
  mesh.faces.push_back(face_g);
  mesh.faces[f].edge = ea;
  // Hand the part v_b ... v_a over to g (bounded by the old face degree).
  std::size_t n = 0;
  for (Index h = eb; h != d1 && n <= degree; h = mesh.edges[h].next, ++n) mesh.edges[h].face = g;
  mesh.edges[d1].face = g;
  // Both parts are closed cycles whose links agree, the diagonal included.
  HEDRA_ASSERT(!consistent || (face_links_agree(mesh, f) && face_links_agree(mesh, g)));
  return g;
}

// ---------------------------------------------------------------------------
// cut_by_plane

const char* to_string(CutStatus status) {
  switch (status) {
    case CutStatus::unchanged:
      return "unchanged";
    case CutStatus::cut:
      return "cut";
    case CutStatus::emptied:
      return "emptied";
    case CutStatus::invalid_plane:
      return "invalid_plane";
    case CutStatus::invalid_mesh:
      return "invalid_mesh";
    case CutStatus::topology_failure:
      return "topology_failure";
  }
  return "unknown";
}

namespace {

// Point and segment hulls: vertices only.
CutResult cut_vertices_only(HalfEdgeMesh& mesh, const Plane& plane, double tol) {
  CutResult result;
  const std::size_t n = mesh.vertices.size();
  double d[2] = {0, 0};
  Side s[2] = {Side::on, Side::on};
  bool any_front = false, any_behind = false;
  for (std::size_t i = 0; i < n; ++i) {
    d[i] = plane.signed_distance(mesh.vertices[i].position);
    s[i] = classify(d[i], tol);
    any_front |= s[i] == Side::front;
    any_behind |= s[i] == Side::behind;
  }
  if (!any_front) return result;
  if (!any_behind) {
    result.status = CutStatus::emptied;
    result.removed_vertices = n;
    mesh.vertices.clear();
    return result;
  }
  // A segment from strictly behind to strictly in front: move the front end
  // onto the plane (it becomes a new vertex; the old one is removed).
  const std::size_t fi = s[0] == Side::front ? 0 : 1;
  const std::size_t bi = 1 - fi;
  mesh.vertices[fi].position = crossing_point(mesh.vertices[bi].position, d[bi], mesh.vertices[fi].position, d[fi]);
  result.status = CutStatus::cut;
  result.removed_vertices = 1;
  result.added_vertices = 1;
  return result;
}

}  // namespace

namespace {

// invalid_mesh when the mesh cannot be cut as it stands (empty, inconsistent
// counts, non-finite positions, links out of range), unchanged otherwise.
// The links every walk of the cut relies on (indices already in range):
// twins pair up, next and prev are inverse, a face's cycle stays on the face
// and a twin starts where the edge ends. A mesh that breaks them would send
// the cut's walks astray, so it is rejected before any of them.
bool links_consistent(const HalfEdgeMesh& mesh) {
  const std::size_t H = mesh.edges.size();
  for (std::size_t e = 0; e < H; ++e) {
    const HalfEdge& h = mesh.edges[e];
    const HalfEdge& next = mesh.edges[h.next];
    if (h.twin == e || mesh.edges[h.twin].twin != e || next.prev != e || mesh.edges[h.prev].next != e) return false;
    if (next.face != h.face || next.origin != mesh.edges[h.twin].origin) return false;
  }
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    if (mesh.faces[f].edge >= H || mesh.edges[mesh.faces[f].edge].face != f) return false;
  return true;
}

CutStatus check_cut_input(const HalfEdgeMesh& mesh) {
  const std::size_t V = mesh.vertices.size(), H = mesh.edges.size(), F = mesh.faces.size();
  if (V == 0 || H % 2 != 0 || (H == 0) != (F == 0)) return CutStatus::invalid_mesh;
  if (V >= kInvalidIndex || H >= kInvalidIndex / 2) return CutStatus::invalid_mesh;
  for (const auto& v : mesh.vertices)
    if (!v.position.allFinite()) return CutStatus::invalid_mesh;
  if (H == 0 && V > 2) return CutStatus::invalid_mesh;
  for (const auto& h : mesh.edges)
    if (h.origin >= V || h.twin >= H || h.next >= H || h.prev >= H || h.face >= F) return CutStatus::invalid_mesh;
  return links_consistent(mesh) ? CutStatus::unchanged : CutStatus::invalid_mesh;
}

// One cut of a mesh with faces, phase by phase (docs/design.md, hull): the
// decisions go to scratch arrays and the kept part into `out`; the input is
// only read.
struct PlaneCut {
  // A corner of a kept polygon: its vertex reference (input vertex v as v,
  // the crossing on an edge as V + crossing index) and the input half-edge
  // its outgoing edge is a piece of (kInvalidIndex for a chord across a
  // removed front run).
  struct Corner {
    Index vertex;
    Index source;
  };

  const HalfEdgeMesh& mesh;
  Plane plane;
  double tol;
  std::size_t V, H, F;
  std::vector<double> dist;
  std::vector<Side> side;
  std::vector<Index> crossing_of;  // per input half-edge: its crossing's reference, or kInvalidIndex
  std::vector<Eigen::Vector3d> crossings;
  std::vector<Corner> corners;
  std::vector<Index> poly_begin;  // corner range of each kept face
  std::vector<Index> kept_faces;
  std::vector<Index> new_index;  // vertex reference -> vertex of out
  HalfEdgeMesh out;
  std::vector<Index> border;  // half-edges of out without a twin yet

#if HEDRA_ASSERTS_ENABLED
  bool input_links_agree;
#endif

  PlaneCut(const HalfEdgeMesh& m, const Plane& p, double t)
      : mesh(m), plane(p), tol(t), V(m.vertices.size()), H(m.edges.size()), F(m.faces.size()) {
#if HEDRA_ASSERTS_ENABLED
    input_links_agree = all_links_agree(m);
#endif
  }

  Index dest(Index o) const { return out.edges[out.edges[o].next].origin; }

  // 1. Classifies the vertices. Returns unchanged (nothing in front),
  //    emptied (nothing behind), invalid_mesh (a distance overflowed), or
  //    cut: go on.
  CutStatus classify_vertices() {
    dist.resize(V);
    side.resize(V);
    bool any_front = false, any_behind = false;
    for (Index v = 0; v < V; ++v) {
      dist[v] = plane.signed_distance(mesh.vertices[v].position);
      if (!std::isfinite(dist[v])) return CutStatus::invalid_mesh;  // coordinates near the overflow limit
      side[v] = classify(dist[v], tol);
      any_front |= side[v] == Side::front;
      any_behind |= side[v] == Side::behind;
    }
    if (!any_front) return CutStatus::unchanged;
    // Without a vertex behind, nothing with thickness is behind the plane
    // (at most a face, edge or vertex lying in it).
    if (!any_behind) return CutStatus::emptied;
    return CutStatus::cut;
  }

  // 2. One new vertex per undirected edge from strictly behind to strictly
  //    in front; false when one overflows.
  bool add_crossings() {
    crossing_of.assign(H, kInvalidIndex);
    for (Index h = 0; h < H; ++h) {
      const Index a = mesh.edges[h].origin, b = mesh.edges[mesh.edges[h].twin].origin;
      if (h > mesh.edges[h].twin) continue;  // once per undirected edge
      const bool cross =
          (side[a] == Side::behind && side[b] == Side::front) || (side[a] == Side::front && side[b] == Side::behind);
      if (!cross) continue;
      const Index bv = side[a] == Side::behind ? a : b, fv = side[a] == Side::behind ? b : a;
      const Index id = static_cast<Index>(V + crossings.size());
      crossings.push_back(crossing_point(mesh.position(bv), dist[bv], mesh.position(fv), dist[fv]));
      if (!crossings.back().allFinite()) return false;  // f - b overflowed
      crossing_of[h] = id;
      crossing_of[mesh.edges[h].twin] = id;
    }
    return true;
  }

  // 3. The kept polygons: a face with a vertex strictly behind keeps its
  //    behind and on-plane corners, and each front run becomes a chord.
  //    False when a face's cycle is broken.
  bool collect_kept_polygons() {
    corners.reserve(H + crossings.size() * 2);
    for (Index f = 0; f < F; ++f) {
      const Index first = static_cast<Index>(corners.size());
      const Index start = mesh.faces[f].edge;
      if (start >= H) return false;
      bool has_behind = false;
      Index h = start;
      std::size_t steps = 0;
      do {
        has_behind |= side[mesh.edges[h].origin] == Side::behind;
        add_corners(h);
        h = mesh.edges[h].next;
        ++steps;
      } while (h != start && steps <= H);
      if (h != start) return false;
      if (has_behind) {
        // A face of >= 3 edges with a vertex behind keeps >= 3 corners
        // (asserted when the input's links agree: bad input is not a bug).
        HEDRA_ASSERT(corners.size() - first >= 3 || !input_links_agree);
        poly_begin.push_back(first);
        kept_faces.push_back(f);
      } else {
        corners.resize(first);
      }
    }
    poly_begin.push_back(static_cast<Index>(corners.size()));
    return true;
  }

  // The corners that input half-edge h = u -> w contributes to its face's
  // kept polygon.
  void add_corners(Index h) {
    const Index u = mesh.edges[h].origin, w = mesh.edges[mesh.edges[h].twin].origin;
    const Side su = side[u], sw = side[w];
    if (su != Side::front) {
      if (sw != Side::front) {
        corners.push_back({u, h});
      } else if (su == Side::behind) {
        corners.push_back({u, h});                           // piece u -> crossing
        corners.push_back({crossing_of[h], kInvalidIndex});  // chord starts here
      } else {
        corners.push_back({u, kInvalidIndex});  // on-plane vertex: chord starts here
      }
    } else if (sw == Side::behind) {
      corners.push_back({crossing_of[h], h});  // piece crossing -> w
    }
  }

  // 4. Compact vertex numbering: kept input vertices in their order, then
  //    the crossings. Only vertices on a kept face survive.
  void number_vertices() {
    const std::size_t refs = V + crossings.size();
    new_index.assign(refs, kInvalidIndex);
    for (const Corner& c : corners) new_index[c.vertex] = 0;
    Index next_vertex = 0;
    for (std::size_t r = 0; r < refs; ++r)
      if (new_index[r] == 0) new_index[r] = next_vertex++;
    out.set_tolerance(mesh.tolerance());
    out.vertices.resize(next_vertex);
    for (std::size_t r = 0; r < refs; ++r) {
      if (new_index[r] == kInvalidIndex) continue;
      out.vertices[new_index[r]].position = r < V ? mesh.vertices[r].position : crossings[r - V];
    }
  }

  // 5. Half-edges of the kept faces; pieces of input half-edges are twinned
  //    through out_of_source, the rest form the border.
  void build_kept_faces() {
    out.edges.resize(corners.size());
    out.faces.resize(kept_faces.size());
    std::vector<Index> out_of_source(H, kInvalidIndex);
    for (std::size_t k = 0; k < kept_faces.size(); ++k) {
      const Index b = poly_begin[k], n = poly_begin[k + 1] - b;
      for (Index i = 0; i < n; ++i) {
        HalfEdge& he = out.edges[b + i];
        he.origin = new_index[corners[b + i].vertex];
        he.next = b + (i + 1) % n;
        he.prev = b + (i + n - 1) % n;
        he.face = static_cast<Index>(k);
        if (corners[b + i].source != kInvalidIndex) out_of_source[corners[b + i].source] = b + i;
      }
      out.faces[k].edge = b;
      out.faces[k].plane = mesh.faces[kept_faces[k]].plane;
    }
    for (Index o = 0; o < corners.size(); ++o) {
      const Index src = corners[o].source;
      const Index t = src == kInvalidIndex ? kInvalidIndex : out_of_source[mesh.edges[src].twin];
      out.edges[o].twin = t;
      if (t == kInvalidIndex) border.push_back(o);
    }
  }

  // 6. Closes the opening: a flat mesh's border half-edges come in opposite
  //    pairs (the chord across the front side and the one across the back)
  //    and become twins; otherwise the border must be one simple loop,
  //    capped. Sets cap (kInvalidIndex when flat); false when neither holds.
  bool close_opening(Index& cap) {
    cap = kInvalidIndex;
    if (border.empty()) return false;
    std::vector<std::pair<std::uint64_t, Index>> keys;
    keys.reserve(border.size());
    auto key = [](Index a, Index b) { return (std::uint64_t(a) << 32) | b; };
    for (Index o : border) keys.push_back({key(out.edges[o].origin, dest(o)), o});
    std::sort(keys.begin(), keys.end());
    std::size_t paired = 0;
    for (Index o : border) {
      const std::uint64_t want = key(dest(o), out.edges[o].origin);
      auto it = std::lower_bound(keys.begin(), keys.end(), std::make_pair(want, Index(0)));
      if (it != keys.end() && it->first == want) {
        out.edges[o].twin = it->second;
        ++paired;
      }
    }
    if (paired == border.size()) {
      for (std::size_t i = 1; i < keys.size(); ++i)
        if (keys[i].first == keys[i - 1].first) return false;  // an edge used twice one way
      return true;
    }
    if (paired != 0) return false;
    return add_cap(cap);
  }

  // The cap face: the reversed border loop, in the cutting plane. False when
  // the border is not one simple closed loop.
  bool add_cap(Index& cap) {
    // The cap half-edge opposite border o = (a -> b) runs b -> a and is
    // followed by the cap half-edge leaving a, the one opposite the border
    // half-edge that ends at a.
    std::vector<Index> border_into(out.vertices.size(), kInvalidIndex);
    for (Index o : border) {
      Index& slot = border_into[dest(o)];
      if (slot != kInvalidIndex) return false;  // the loop would pass a vertex twice
      slot = o;
    }
    const Index n = static_cast<Index>(border.size());
    if (n < 3) return false;
    cap = static_cast<Index>(out.faces.size());
    const Index cap_first = static_cast<Index>(out.edges.size());
    std::vector<Index> cap_of_border(out.edges.size(), kInvalidIndex);
    for (Index i = 0; i < n; ++i) cap_of_border[border[i]] = cap_first + i;
    out.edges.resize(cap_first + n);
    for (Index i = 0; i < n; ++i) {
      const Index o = border[i];
      const Index into_origin = border_into[out.edges[o].origin];
      if (into_origin == kInvalidIndex) return false;  // the border is not closed
      HalfEdge& c = out.edges[cap_first + i];
      c.origin = dest(o);
      c.twin = o;
      c.face = cap;
      c.next = cap_of_border[into_origin];
      out.edges[o].twin = cap_first + i;
    }
    for (Index i = 0; i < n; ++i) out.edges[out.edges[cap_first + i].next].prev = cap_first + i;
    // One loop, not several: walking from the first cap half-edge must visit
    // all of them.
    Index c = cap_first;
    Index steps = 0;
    do {
      c = out.edges[c].next;
      ++steps;
    } while (c != cap_first && steps <= n);
    if (steps != n) return false;
    Face cap_face;
    cap_face.edge = cap_first;
    cap_face.plane = plane;
    out.faces.push_back(cap_face);
    return true;
  }
};

}  // namespace

CutResult cut_by_plane(HalfEdgeMesh& mesh, const Plane& plane_in) {
  CutResult result;
  Plane plane;
  if (!normalized_plane(plane_in, plane)) {
    result.status = CutStatus::invalid_plane;
    return result;
  }
  result.status = check_cut_input(mesh);
  if (result.status != CutStatus::unchanged) return result;
  const double tol = mesh_tolerance(mesh);
  if (mesh.edges.empty()) return cut_vertices_only(mesh, plane, tol);

  PlaneCut cut(mesh, plane, tol);
  result.status = cut.classify_vertices();
  if (result.status == CutStatus::emptied) {
    result.removed_vertices = mesh.vertices.size();
    mesh.vertices.clear();
    mesh.edges.clear();
    mesh.faces.clear();
    return result;
  }
  if (result.status != CutStatus::cut) return result;
  if (!cut.add_crossings() || !cut.collect_kept_polygons()) {
    result.status = CutStatus::invalid_mesh;
    return result;
  }
  cut.number_vertices();
  cut.build_kept_faces();
  Index cap = kInvalidIndex;
  if (!cut.close_opening(cap)) {
    result.status = CutStatus::topology_failure;
    return result;
  }
  cut.out.rebuild_vertex_links();
  // A consistent input gives consistent links.
  HEDRA_ASSERT(!cut.input_links_agree || all_links_agree(cut.out));

  result.status = CutStatus::cut;
  result.cap_face = cap;
  result.added_vertices = cut.crossings.size();
  result.removed_vertices = cut.V - (cut.out.vertices.size() - cut.crossings.size());
  result.face_source = cut.kept_faces;
  if (cap != kInvalidIndex) result.face_source.push_back(kInvalidIndex);
  mesh = std::move(cut.out);
  return result;
}

// ---------------------------------------------------------------------------
// clip_polygon

ClipResult clip_polygon(const Eigen::Vector3d* points, std::size_t count, const Plane& plane_in, Eigen::Vector3d* out,
                        std::size_t capacity, double tolerance) {
  ClipResult result;
  Plane plane;
  if (!normalized_plane(plane_in, plane) || (count > 0 && points == nullptr)) {
    result.status = ClipStatus::invalid_input;
    return result;
  }
  double extent = std::abs(plane.offset);
  for (std::size_t i = 0; i < count; ++i) {
    if (!points[i].allFinite()) {
      result.status = ClipStatus::invalid_input;
      return result;
    }
    extent = std::max(extent, points[i].cwiseAbs().maxCoeff());
  }
  const double tol = tolerance > 0 && std::isfinite(tolerance) ? tolerance : extent_tolerance(extent);
  auto emit = [&](const Eigen::Vector3d& p) {
    if (!p.allFinite()) {  // a crossing of points near the overflow limit
      result.status = ClipStatus::invalid_input;
      result.count = 0;
      return false;
    }
    if (result.count == capacity) {
      result.status = ClipStatus::capacity_exceeded;
      return false;
    }
    out[result.count++] = p;
    return true;
  };
  if (count == 0) return result;
  if (count <= 2) {
    // A point, or a segment (whose "closing edge" is the segment itself, so
    // the polygon walk below would emit its crossing twice).
    const double d0 = plane.signed_distance(points[0]);
    const Side s0 = classify(d0, tol);
    if (count == 1) {
      if (s0 != Side::front) emit(points[0]);
      return result;
    }
    const double d1 = plane.signed_distance(points[1]);
    const Side s1 = classify(d1, tol);
    if (s0 != Side::front && !emit(points[0])) return result;
    if (s0 == Side::behind && s1 == Side::front && !emit(crossing_point(points[0], d0, points[1], d1))) return result;
    if (s0 == Side::front && s1 == Side::behind && !emit(crossing_point(points[1], d1, points[0], d0))) return result;
    if (s1 != Side::front) emit(points[1]);
    return result;
  }
  double d_cur = plane.signed_distance(points[0]);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t j = i + 1 == count ? 0 : i + 1;
    const double d_next = plane.signed_distance(points[j]);
    const Side s_cur = classify(d_cur, tol), s_next = classify(d_next, tol);
    if (s_cur != Side::front && !emit(points[i])) return result;
    if (s_cur == Side::behind && s_next == Side::front) {
      if (!emit(crossing_point(points[i], d_cur, points[j], d_next))) return result;
    } else if (s_cur == Side::front && s_next == Side::behind) {
      if (!emit(crossing_point(points[j], d_next, points[i], d_cur))) return result;
    }
    d_cur = d_next;
  }
  return result;
}

}  // namespace hedra::hull
