// Index-based half-edge (DCEL) structure for closed convex polyhedra.
//
// Storage: three flat arrays (vertices, half-edges, faces) addressed by 32-bit
// indices; no per-element heap allocation. Conventions:
//   * a face lies to the LEFT of each of its half-edges; seen from outside the
//     solid, a face's half-edges run counter-clockwise;
//   * twin(e) runs the other way along the same edge, in the neighbouring face;
//   * origin(e) is the vertex e leaves; destination(e) = origin(twin(e));
//   * vertex.edge is one half-edge leaving the vertex, face.edge one half-edge
//     of the face; face.plane is {unit normal pointing out, offset} with
//     normal . x = offset on the face.
// Invariants (checked by validate()):
//   twin(twin(e)) = e != twin(e); next(prev(e)) = prev(next(e)) = e;
//   face(next(e)) = face(e); origin(next(e)) = destination(e);
//   origin(vertex.edge) = vertex; face(face.edge) = face; every face has >= 3
//   edges; the surface is a closed 2-manifold with V - E + F = 2 (each vertex's
//   ring of half-edges is a single cycle); every face is planar and convex and
//   every vertex is on or behind every face plane, within tolerance().
//
// Degenerate hulls: a single point (one vertex, no edges) and a segment (two
// vertices, no edges) are represented by vertices only; a flat convex polygon
// is two back-to-back faces sharing one ring of edges (V - E + F = 2 holds).
// dimension() tells which.
//
// Rotation around a vertex, seen from outside: rotate_ccw(e) = twin(prev(e)),
// rotate_cw(e) = next(twin(e)); both map an outgoing half-edge of a vertex to
// the neighbouring outgoing half-edge.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace hedra::hull {

using Index = std::uint32_t;
inline constexpr Index kInvalidIndex = std::numeric_limits<Index>::max();

struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, pointing out of the solid
  double offset = 0.0;                               // normal . x = offset on the plane

  double signed_distance(const Eigen::Vector3d& p) const { return normal.dot(p) - offset; }
};

// Plane of a polygon given by n vertices (pos(i) returns vertex i, in order):
// Newell's normal, N = sum (p_i - c) x (p_{i+1} - c) around the vertex
// average c (so large coordinates do not cancel), made exactly perpendicular
// to the polygon's longest edge. For a sliver (a thin triangle whose vertices
// are nearly collinear) the cross products' rounding tilts N about the
// sliver's short axis; removing N's component along the longest edge undoes
// that tilt, so both ends of the long edge sit at the same height. *area gets
// the polygon's area (|N| / 2). A degenerate polygon gets a zero normal.
template <class PositionAt>
Plane polygon_plane(std::size_t n, PositionAt pos, double* area = nullptr) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) c += pos(i);
  c /= static_cast<double>(n > 0 ? n : 1);
  Eigen::Vector3d normal = Eigen::Vector3d::Zero(), longest = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d a = pos(i) - c, b = pos(i + 1 == n ? 0 : i + 1) - c;
    normal += a.cross(b);
    const Eigen::Vector3d edge = b - a;
    if (edge.squaredNorm() > longest.squaredNorm()) longest = edge;
  }
  if (area) *area = 0.5 * normal.norm();
  const double ll = longest.squaredNorm();
  if (ll > 0) normal -= (normal.dot(longest) / ll) * longest;
  const double len = normal.norm();
  Plane plane;
  if (len > 0 && std::isfinite(len)) {
    plane.normal = normal / len;
    plane.offset = plane.normal.dot(c);
  }
  return plane;
}

struct Vertex {
  Eigen::Vector3d position;
  Index edge = kInvalidIndex;  // a half-edge leaving this vertex
};

struct HalfEdge {
  Index origin = kInvalidIndex;  // the vertex this half-edge leaves
  Index twin = kInvalidIndex;
  Index next = kInvalidIndex;
  Index prev = kInvalidIndex;
  Index face = kInvalidIndex;  // the face on the left
};

struct Face {
  Index edge = kInvalidIndex;  // one half-edge of this face
  Plane plane;
};

// What validate() found: an empty list means every invariant holds.
struct ValidationReport {
  std::vector<std::string> errors;
  bool ok() const { return errors.empty(); }
  std::string to_string() const;  // one error per line
};

class HalfEdgeMesh;

// A cheap forward range over a cycle of half-edges: starts at `start`, applies
// Step until it comes back to `start`, and yields Project(half-edge). Assumes a
// valid mesh (use validate() on untrusted structures first).
template <class Step, class Project>
class HalfEdgeCycle {
 public:
  class iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = Index;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = Index;

    iterator() = default;
    iterator(const HalfEdgeMesh* mesh, Index start, Index current, bool done)
        : mesh_(mesh), start_(start), current_(current), done_(done) {}
    Index operator*() const { return Project{}(*mesh_, current_); }
    iterator& operator++() {
      current_ = Step{}(*mesh_, current_);
      done_ = current_ == start_;
      return *this;
    }
    iterator operator++(int) {
      iterator copy = *this;
      ++*this;
      return copy;
    }
    bool operator==(const iterator& o) const { return current_ == o.current_ && done_ == o.done_; }
    bool operator!=(const iterator& o) const { return !(*this == o); }

   private:
    const HalfEdgeMesh* mesh_ = nullptr;
    Index start_ = kInvalidIndex;
    Index current_ = kInvalidIndex;
    bool done_ = true;
  };

  HalfEdgeCycle(const HalfEdgeMesh& mesh, Index start) : mesh_(&mesh), start_(start) {}
  iterator begin() const { return {mesh_, start_, start_, start_ == kInvalidIndex}; }
  iterator end() const { return {mesh_, start_, start_, true}; }

 private:
  const HalfEdgeMesh* mesh_;
  Index start_;
};

class HalfEdgeMesh {
 public:
  // ---- storage -----------------------------------------------------------
  std::vector<Vertex> vertices;
  std::vector<HalfEdge> edges;  // half-edges; edge e and twin(e) both stored
  std::vector<Face> faces;

  // ---- size and tolerance -------------------------------------------------
  std::size_t vertex_count() const { return vertices.size(); }
  std::size_t half_edge_count() const { return edges.size(); }
  std::size_t edge_count() const { return edges.size() / 2; }
  std::size_t face_count() const { return faces.size(); }
  // 0 point, 1 segment, 2 flat polygon (two back-to-back faces), 3 solid;
  // -1 when empty.
  int dimension() const;

  // Distance below which a point counts as on a plane; validate() and the
  // editing operations use it. Set by the builder from the input's extent.
  double tolerance() const { return tolerance_; }
  void set_tolerance(double t) { tolerance_ = t; }

  // ---- navigation ---------------------------------------------------------
  Index origin(Index e) const { return edges[e].origin; }
  Index destination(Index e) const { return edges[edges[e].twin].origin; }
  Index twin(Index e) const { return edges[e].twin; }
  Index next(Index e) const { return edges[e].next; }
  Index prev(Index e) const { return edges[e].prev; }
  Index left_face(Index e) const { return edges[e].face; }
  Index right_face(Index e) const { return edges[edges[e].twin].face; }
  // Neighbouring outgoing half-edge of origin(e), counter-clockwise / clockwise
  // seen from outside.
  Index rotate_ccw(Index e) const { return edges[edges[e].prev].twin; }
  Index rotate_cw(Index e) const { return edges[edges[e].twin].next; }

  const Eigen::Vector3d& position(Index v) const { return vertices[v].position; }
  const Plane& plane(Index f) const { return faces[f].plane; }
  Eigen::Vector3d edge_vector(Index e) const { return position(destination(e)) - position(origin(e)); }

  // ---- ranges (usable in range-for) --------------------------------------
  struct NextStep {
    Index operator()(const HalfEdgeMesh& m, Index e) const { return m.next(e); }
  };
  struct RotateStep {
    Index operator()(const HalfEdgeMesh& m, Index e) const { return m.rotate_ccw(e); }
  };
  struct AsEdge {
    Index operator()(const HalfEdgeMesh&, Index e) const { return e; }
  };
  struct AsTwin {
    Index operator()(const HalfEdgeMesh& m, Index e) const { return m.twin(e); }
  };
  struct AsOrigin {
    Index operator()(const HalfEdgeMesh& m, Index e) const { return m.origin(e); }
  };
  struct AsDestination {
    Index operator()(const HalfEdgeMesh& m, Index e) const { return m.destination(e); }
  };
  struct AsLeftFace {
    Index operator()(const HalfEdgeMesh& m, Index e) const { return m.left_face(e); }
  };
  struct AsRightFace {
    Index operator()(const HalfEdgeMesh& m, Index e) const { return m.right_face(e); }
  };

  // A face's half-edges, vertices and neighbouring faces, counter-clockwise.
  HalfEdgeCycle<NextStep, AsEdge> face_edges(Index f) const { return {*this, faces[f].edge}; }
  HalfEdgeCycle<NextStep, AsOrigin> face_vertices(Index f) const { return {*this, faces[f].edge}; }
  HalfEdgeCycle<NextStep, AsRightFace> face_neighbors(Index f) const { return {*this, faces[f].edge}; }
  // A vertex's outgoing and incoming half-edges, neighbour vertices and
  // incident faces, counter-clockwise seen from outside. Empty for a vertex
  // without edges (point and segment hulls).
  HalfEdgeCycle<RotateStep, AsEdge> vertex_outgoing(Index v) const { return {*this, vertices[v].edge}; }
  HalfEdgeCycle<RotateStep, AsTwin> vertex_incoming(Index v) const { return {*this, vertices[v].edge}; }
  HalfEdgeCycle<RotateStep, AsDestination> vertex_neighbors(Index v) const { return {*this, vertices[v].edge}; }
  HalfEdgeCycle<RotateStep, AsLeftFace> vertex_faces(Index v) const { return {*this, vertices[v].edge}; }

  std::size_t face_degree(Index f) const;    // number of edges of face f
  std::size_t vertex_degree(Index v) const;  // number of edges at vertex v

  // ---- geometry -----------------------------------------------------------
  // Recomputes face f's plane: Newell's normal of its polygon (robust for
  // non-triangular, slightly non-planar polygons) through the vertex average.
  void update_plane(Index f);
  void update_planes();
  Eigen::Vector3d face_centroid(Index f) const;  // average of the face's vertices
  // Index of a vertex maximising direction . position (linear scan).
  Index extreme_vertex(const Eigen::Vector3d& direction) const;

  // ---- construction and checking -----------------------------------------
  // Builds a mesh from vertex positions and polygons (vertex indices,
  // counter-clockwise seen from outside). Twins are matched by vertex pairs;
  // returns false and says why in *error when the polygons do not form a
  // closed 2-manifold (an edge used twice the same way, an open edge, a face
  // with fewer than 3 vertices, an index out of range).
  static bool from_polygons(const std::vector<Eigen::Vector3d>& positions,
                            const std::vector<std::vector<Index>>& polygons, HalfEdgeMesh& out,
                            std::string* error = nullptr);
  // The polygons of the faces (vertex indices, counter-clockwise from outside).
  std::vector<std::vector<Index>> polygons() const;

  // Checks every invariant listed at the top of this file; geometric checks
  // use `tolerance` (default: tolerance()). Never loops forever on a corrupt
  // structure. Convexity is checked locally at every edge (the vertices next
  // to the edge in the neighbouring face lie behind the face's plane), which
  // for a closed, consistently oriented surface implies global convexity,
  // and each face must wind exactly once around its normal (no star polygon,
  // no sliver whose turns cancel). `exhaustive` adds the global check that
  // every vertex is behind every face plane (brute force when V * F <= 5e7,
  // otherwise by hill-climbing to each face normal's extreme vertex, exact
  // once local convexity holds). Without it the checks are O(E).
  ValidationReport validate() const { return validate(tolerance_); }
  ValidationReport validate(double tolerance, bool exhaustive = true) const;

  // Sets each vertex's outgoing half-edge from the half-edge array.
  void rebuild_vertex_links();

 private:
  double tolerance_ = 0.0;
};

}  // namespace hedra::hull
