// Half-edge mesh: plane fitting, construction from polygons, and the
// validator. The validator never trusts the structure: every walk is bounded
// by the number of half-edges and every index is range-checked before use.
#include <algorithm>
#include <cmath>
#include <hedra/hull/half_edge_mesh.hpp>
#include <sstream>
#include <unordered_map>

#include "mesh_checks.hpp"

namespace hedra::hull {

std::string ValidationReport::to_string() const {
  std::string s;
  for (const auto& e : errors) {
    s += e;
    s += '\n';
  }
  return s;
}

int HalfEdgeMesh::dimension() const {
  if (vertices.empty()) return -1;
  if (faces.empty()) return vertices.size() == 1 ? 0 : 1;
  return faces.size() == 2 ? 2 : 3;
}

std::size_t HalfEdgeMesh::face_degree(Index f) const {
  std::size_t n = 0;
  for (Index e : face_edges(f)) {
    (void)e;
    ++n;
  }
  return n;
}

std::size_t HalfEdgeMesh::vertex_degree(Index v) const {
  std::size_t n = 0;
  for (Index e : vertex_outgoing(v)) {
    (void)e;
    ++n;
  }
  return n;
}

Eigen::Vector3d HalfEdgeMesh::face_centroid(Index f) const {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  double n = 0;
  for (Index v : face_vertices(f)) {
    c += position(v);
    n += 1;
  }
  return n > 0 ? Eigen::Vector3d(c / n) : c;
}

void HalfEdgeMesh::update_plane(Index f) {
  // The face's vertices in order, gathered once (faces are small; a flat
  // hull's two faces may be large, and this runs once per face).
  thread_local std::vector<Index> ring;
  ring.clear();
  for (Index v : face_vertices(f)) ring.push_back(v);
  faces[f].plane =
      polygon_plane(ring.size(), [&](std::size_t i) -> const Eigen::Vector3d& { return position(ring[i]); });
}

void HalfEdgeMesh::update_planes() {
  for (Index f = 0; f < faces.size(); ++f) update_plane(f);
}

Index HalfEdgeMesh::extreme_vertex(const Eigen::Vector3d& d) const {
  Index best = kInvalidIndex;
  double best_value = -std::numeric_limits<double>::infinity();
  for (Index v = 0; v < vertices.size(); ++v) {
    const double value = d.dot(vertices[v].position);
    if (value > best_value) {
      best_value = value;
      best = v;
    }
  }
  return best;
}

void HalfEdgeMesh::rebuild_vertex_links() {
  for (auto& v : vertices) v.edge = kInvalidIndex;
  for (Index e = 0; e < edges.size(); ++e) {
    const Index v = edges[e].origin;
    if (v < vertices.size() && vertices[v].edge == kInvalidIndex) vertices[v].edge = e;
  }
}

std::vector<std::vector<Index>> HalfEdgeMesh::polygons() const {
  std::vector<std::vector<Index>> out;
  out.reserve(faces.size());
  for (Index f = 0; f < faces.size(); ++f) {
    std::vector<Index> poly;
    for (Index v : face_vertices(f)) poly.push_back(v);
    out.push_back(std::move(poly));
  }
  return out;
}

bool HalfEdgeMesh::from_polygons(const std::vector<Eigen::Vector3d>& positions,
                                 const std::vector<std::vector<Index>>& polygons, HalfEdgeMesh& out,
                                 std::string* error) {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  HalfEdgeMesh m;
  m.vertices.reserve(positions.size());
  for (const auto& p : positions) m.vertices.push_back({p, kInvalidIndex});
  std::size_t half_edges = 0;
  for (const auto& poly : polygons) half_edges += poly.size();
  m.edges.reserve(half_edges);
  m.faces.reserve(polygons.size());
  std::unordered_map<std::uint64_t, Index> by_vertices;  // (origin, destination) -> half-edge
  by_vertices.reserve(half_edges * 2);
  auto key = [](Index a, Index b) { return (std::uint64_t(a) << 32) | b; };

  for (std::size_t f = 0; f < polygons.size(); ++f) {
    const auto& poly = polygons[f];
    if (poly.size() < 3) return fail("face " + std::to_string(f) + " has fewer than 3 vertices");
    const Index first = static_cast<Index>(m.edges.size());
    const Index n = static_cast<Index>(poly.size());
    for (Index i = 0; i < n; ++i) {
      const Index a = poly[i];
      const Index b = poly[(i + 1) % n];
      if (a >= positions.size() || b >= positions.size())
        return fail("face " + std::to_string(f) + " has a vertex index out of range");
      if (a == b) return fail("face " + std::to_string(f) + " repeats vertex " + std::to_string(a));
      HalfEdge h;
      h.origin = a;
      h.face = static_cast<Index>(f);
      h.next = first + (i + 1) % n;
      h.prev = first + (i + n - 1) % n;
      const Index e = static_cast<Index>(m.edges.size());
      if (!by_vertices.emplace(key(a, b), e).second)
        return fail("edge " + std::to_string(a) + "->" + std::to_string(b) + " is used twice in the same direction");
      m.edges.push_back(h);
    }
    Face face;
    face.edge = first;
    m.faces.push_back(face);
  }
  for (Index e = 0; e < m.edges.size(); ++e) {
    const Index a = m.edges[e].origin;
    const Index b = m.edges[m.edges[e].next].origin;
    auto it = by_vertices.find(key(b, a));
    if (it == by_vertices.end())
      return fail("edge " + std::to_string(a) + "->" + std::to_string(b) + " has no opposite (open surface)");
    m.edges[e].twin = it->second;
  }
  m.rebuild_vertex_links();
  m.update_planes();
  // A tolerance in the spirit of the builder's, from the extent of the input.
  double extent = 0;
  for (const auto& p : positions) extent = std::max(extent, p.cwiseAbs().maxCoeff());
  m.tolerance_ = 16 * std::numeric_limits<double>::epsilon() * std::max(extent, 1e-300) * 3;
  out = std::move(m);
  return true;
}

namespace {

// Collects validate()'s messages, at most 64 of them.
struct Reporter {
  ValidationReport& r;
  void operator()(const std::string& s) const {
    if (r.errors.size() < 64) r.errors.push_back(s);
  }
};

// A point or segment hull (no faces): one or two distinct vertices.
void check_vertices_only(const HalfEdgeMesh& m, double tol, const Reporter& err) {
  const std::size_t V = m.vertices.size();
  if (V == 0) err("mesh is empty");
  if (V > 2) err("mesh has " + std::to_string(V) + " vertices but no faces");
  if (V == 2 && (m.vertices[0].position - m.vertices[1].position).norm() <= tol)
    err("segment hull has coincident end points");
}

// Every stored index in range, so that the later checks can follow links.
bool indices_in_range(const HalfEdgeMesh& m, const Reporter& err) {
  const std::size_t V = m.vertices.size(), H = m.edges.size(), F = m.faces.size();
  bool ok = true;
  for (Index e = 0; e < H; ++e) {
    const HalfEdge& h = m.edges[e];
    if (h.origin >= V || h.twin >= H || h.next >= H || h.prev >= H || h.face >= F) {
      err("half-edge " + std::to_string(e) + " has an index out of range");
      ok = false;
    }
  }
  for (Index f = 0; f < F; ++f) {
    if (m.faces[f].edge >= H) {
      err("face " + std::to_string(f) + " has an edge index out of range");
      ok = false;
    }
  }
  for (Index v = 0; v < V; ++v) {
    if (m.vertices[v].edge >= H) {
      err("vertex " + std::to_string(v) + " has no valid outgoing half-edge");
      ok = false;
    }
  }
  return ok;
}

// The local link invariants of each half-edge (twin, next/prev, face, origin).
void check_links(const HalfEdgeMesh& m, const Reporter& err) {
  const auto& edges = m.edges;
  for (Index e = 0; e < edges.size(); ++e) {
    const HalfEdge& h = edges[e];
    // Names are built only when an error is reported (this loop is hot).
    const auto name = [e] { return "half-edge " + std::to_string(e); };
    if (h.twin == e) err(name() + " is its own twin");
    if (edges[h.twin].twin != e) err(name() + ": twin(twin(e)) != e");
    if (edges[h.prev].next != e) err(name() + ": next(prev(e)) != e");
    if (edges[h.next].prev != e) err(name() + ": prev(next(e)) != e");
    if (edges[h.next].face != h.face) err(name() + ": face(next(e)) != face(e)");
    if (edges[h.next].origin != edges[h.twin].origin) err(name() + ": origin(next(e)) != destination(e)");
    if (h.origin == edges[h.twin].origin) err(name() + " starts and ends at the same vertex");
  }
}

// Each face's cycle has >= 3 edges, and the cycles cover every half-edge
// exactly once; vertex.edge leaves its vertex.
void check_face_cycles(const HalfEdgeMesh& m, const Reporter& err) {
  const std::size_t V = m.vertices.size(), H = m.edges.size(), F = m.faces.size();
  for (Index v = 0; v < V; ++v) {
    if (m.edges[m.vertices[v].edge].origin != v) err("vertex " + std::to_string(v) + ": origin(vertex.edge) != vertex");
  }
  std::vector<Index> seen_face(H, kInvalidIndex);
  for (Index f = 0; f < F; ++f) {
    if (m.edges[m.faces[f].edge].face != f) err("face " + std::to_string(f) + ": face(face.edge) != face");
    Index e = m.faces[f].edge;
    std::size_t n = 0;
    do {
      if (seen_face[e] != kInvalidIndex) {
        err("half-edge " + std::to_string(e) + " is in the cycles of two faces");
        break;
      }
      seen_face[e] = f;
      e = m.edges[e].next;
      ++n;
    } while (e != m.faces[f].edge && n <= H);
    if (n < 3) err("face " + std::to_string(f) + " has fewer than 3 edges");
  }
  for (Index e = 0; e < H; ++e) {
    if (seen_face[e] == kInvalidIndex) err("half-edge " + std::to_string(e) + " is in no face's cycle");
  }
}

// Vertex rings: the rotation cycle from vertex.edge reaches every outgoing
// half-edge of the vertex (a single fan: the surface is a manifold there).
void check_vertex_rings(const HalfEdgeMesh& m, const Reporter& err) {
  const std::size_t V = m.vertices.size(), H = m.edges.size();
  std::vector<std::size_t> outgoing(V, 0);
  for (Index e = 0; e < H; ++e) ++outgoing[m.edges[e].origin];
  for (Index v = 0; v < V; ++v) {
    if (outgoing[v] == 0) {
      err("vertex " + std::to_string(v) + " has no edges");
      continue;
    }
    Index e = m.vertices[v].edge;
    std::size_t n = 0;
    do {
      e = m.rotate_ccw(e);
      ++n;
    } while (e != m.vertices[v].edge && n <= H && m.edges[e].origin == v);
    if (m.edges[e].origin != v || n != outgoing[v])
      err("vertex " + std::to_string(v) + " is not a manifold vertex (its ring has " + std::to_string(n) + " of " +
          std::to_string(outgoing[v]) + " edges)");
  }
}

// Face f is planar within tol, wound along its normal, convex at each vertex
// (turning once), and the vertices next to each of its edges in the
// neighbouring faces are behind its plane. Needs consistent links (the
// vertex after edge i's is its destination); `ring` is scratch space.
void check_face_geometry(const HalfEdgeMesh& m, Index f, double tol, const Reporter& err, std::vector<Index>& ring) {
  const Plane& pl = m.faces[f].plane;
  const auto name = [f] { return "face " + std::to_string(f); };
  if (!pl.normal.allFinite() || std::abs(pl.normal.norm() - 1.0) > 1e3 * std::numeric_limits<double>::epsilon()) {
    err(name() + " has a plane normal that is not unit length");
    return;
  }
  // The vertices in order, gathered once; the centroid as face_centroid()
  // computes it.
  ring.clear();
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (Index v : m.face_vertices(f)) {
    ring.push_back(v);
    c += m.position(v);
  }
  const std::size_t n = ring.size();
  if (n > 0) c = Eigen::Vector3d(c / static_cast<double>(n));
  // Winding agrees with the normal: Newell's vector points along it.
  Eigen::Vector3d newell = Eigen::Vector3d::Zero();
  // The turning angle adds up atan2(sine, cosine) of each corner in order;
  // the first three wait, since a triangle may not need them (below).
  double turning = 0, sines[3] = {}, cosines[3] = {};
  int corners = 0, turns = 0, left_turns = 0;
  const auto add_waiting = [&] {
    for (int i = 0; i < std::min(turns, 3); ++i) turning += std::atan2(sines[i], cosines[i]);
  };
  // Corner i's a - c and edge b - a are corner i - 1's b - c and next edge:
  // carried over, not recomputed (the same differences of the same points).
  Eigen::Vector3d a_c = Eigen::Vector3d::Zero(), d = Eigen::Vector3d::Zero();
  double dl = 0;
  if (n > 0) {
    a_c = m.position(ring[0]) - c;
    d = m.position(ring[1 % n]) - m.position(ring[0]);
    dl = d.norm();
  }
  for (std::size_t i = 0; i < n; ++i) {
    ++corners;
    const Index va = ring[i], vb = ring[(i + 1) % n], vc = ring[(i + 2) % n];
    const Eigen::Vector3d& a = m.position(va);
    const Eigen::Vector3d& b = m.position(vb);
    const Eigen::Vector3d b_c = b - c;
    newell += a_c.cross(b_c);
    if (std::abs(pl.signed_distance(a)) > tol)
      err(name() + ": vertex " + std::to_string(va) + " is " + std::to_string(pl.signed_distance(a)) +
          " off the face plane");
    // Local convexity: the vertex after the next one lies inside the side
    // plane of e (the plane through e containing the face normal).
    const Eigen::Vector3d dn = m.position(vc) - b;
    const double dnl = dn.norm();
    if (dl > 0 && dnl > 0) {
      const Eigen::Vector3d side = d.cross(pl.normal) / dl;  // outward in the face plane
      if (side.dot(dn) > tol)
        err(name() + " is not convex at vertex " + std::to_string(vb) + " (turns outward by " +
            std::to_string(side.dot(dn)) + ")");
      const double turn_sine = d.cross(dn).dot(pl.normal);
      left_turns += turn_sine > 0;
      if (turns < 3) {
        sines[turns] = turn_sine, cosines[turns] = d.dot(dn);
      } else {
        if (turns == 3) add_waiting();
        turning += std::atan2(turn_sine, d.dot(dn));
      }
      ++turns;
    }
    a_c = b_c, d = dn, dl = dnl;
  }
  if (newell.dot(pl.normal) <= 0) err(name() + " is wound against its plane normal");
  // A convex polygon turns exactly once; a star-shaped one more often. The
  // total is a whole number of turns up to rounding, and on faces whose
  // edges are a few tolerances long (a cut just past a vertex) that rounding
  // reaches 1e-5, so half a turn is the threshold that separates the two.
  // A triangle turning left at all three corners turns between half a turn
  // and one and a half (its edges are coplanar; at most one of its exterior
  // angles is below a right angle): nothing to add up.
  const bool left_triangle = corners == 3 && left_turns == 3;
  if (!left_triangle) {
    if (turns <= 3) add_waiting();
    if (std::abs(turning - 2 * M_PI) > M_PI) err(name() + " winds " + std::to_string(turning / (2 * M_PI)) + " times");
  }
  // Convex edges: the vertices next to each edge in the neighbouring face
  // are behind this face's plane (one vertex, checked once, when that face
  // is a triangle).
  for (Index e : m.face_edges(f)) {
    const Index t = m.twin(e);
    const Index w0 = m.destination(m.next(t)), w1 = m.origin(m.prev(t));
    const double s0 = pl.signed_distance(m.position(w0));
    const double s1 = w1 == w0 ? s0 : pl.signed_distance(m.position(w1));
    for (const auto& [w, s] : {std::pair(w0, s0), std::pair(w1, s1)}) {
      if (s > tol)
        err("edge " + std::to_string(m.origin(e)) + "-" + std::to_string(m.destination(e)) + " is concave: vertex " +
            std::to_string(w) + " is " + std::to_string(s) + " in front of " + name());
    }
  }
}

// Every vertex behind every face plane: all pairs when V * F is moderate,
// otherwise a hill-climb to each plane's extreme vertex (exact on a convex,
// locally valid mesh).
void check_containment(const HalfEdgeMesh& m, double tol, const Reporter& err) {
  const std::size_t V = m.vertices.size(), F = m.faces.size();
  if (static_cast<double>(V) * static_cast<double>(F) <= 5e7) {
    for (Index f = 0; f < F; ++f) {
      const Plane& pl = m.faces[f].plane;
      for (Index v = 0; v < V; ++v) {
        const double s = pl.signed_distance(m.vertices[v].position);
        if (s > tol) {
          err("vertex " + std::to_string(v) + " is " + std::to_string(s) + " in front of face " + std::to_string(f));
          break;
        }
      }
    }
    return;
  }
  Index v = 0;
  for (Index f = 0; f < F; ++f) {
    const Plane& pl = m.faces[f].plane;
    double best = pl.normal.dot(m.position(v));
    for (std::size_t step = 0; step <= V; ++step) {
      Index next_v = v;
      for (Index w : m.vertex_neighbors(v)) {
        const double value = pl.normal.dot(m.position(w));
        if (value > best) best = value, next_v = w;
      }
      if (next_v == v) break;
      v = next_v;
    }
    if (best - pl.offset > tol)
      err("vertex " + std::to_string(v) + " is " + std::to_string(best - pl.offset) + " in front of face " +
          std::to_string(f));
  }
}

}  // namespace

// The checks run in order, each only when the ones before found the links
// sound enough to follow: indices, links, cycles and rings, Euler, geometry,
// containment (exhaustive only).
ValidationReport HalfEdgeMesh::validate(double tol, bool exhaustive) const {
  ValidationReport r;
  const Reporter err{r};
  const std::size_t V = vertices.size(), H = edges.size(), F = faces.size();
  for (Index v = 0; v < V; ++v) {
    if (!vertices[v].position.allFinite()) err("vertex " + std::to_string(v) + " has a non-finite position");
  }
  if (H == 0 && F == 0) {
    check_vertices_only(*this, tol, err);
    return r;
  }
  if (H % 2 != 0) err("odd number of half-edges");
  if (!indices_in_range(*this, err)) return r;
  check_links(*this, err);
  if (!r.ok()) return r;
  check_face_cycles(*this, err);
  check_vertex_rings(*this, err);
  if (!r.ok()) return r;
  const long long euler = static_cast<long long>(V) - static_cast<long long>(H / 2) + static_cast<long long>(F);
  if (euler != 2) err("Euler characteristic V - E + F = " + std::to_string(euler) + ", expected 2");
  std::vector<Index> ring;
  for (Index f = 0; f < F; ++f) check_face_geometry(*this, f, tol, err, ring);
  if (!exhaustive || !r.ok()) return r;
  check_containment(*this, tol, err);
  return r;
}

ValidationReport detail::validate_rings_and_faces(const HalfEdgeMesh& mesh, double tol) {
  ValidationReport r;
  const Reporter err{r};
  check_vertex_rings(mesh, err);
  if (!r.ok()) return r;
  std::vector<Index> ring;
  for (Index f = 0; f < mesh.faces.size(); ++f) check_face_geometry(mesh, f, tol, err, ring);
  return r;
}

}  // namespace hedra::hull
