// Convex shapes of hedra::collision, each in its own local frame.
//
//   Sphere       centre at the origin, `radius`.
//   Box          centred, axis-aligned in its frame, `half_extents`.
//   Capsule      the segment from (0,0,-half_length) to (0,0,+half_length)
//                swept by a ball of `radius`.
//   Cylinder     axis z, `radius`, from z = -half_length to +half_length.
//   Cone         axis z, apex at (0,0,+half_length), base disc of `radius`
//                at z = -half_length.
//   Polyhedron   a shared, immutable ConvexPolyhedron (the convex hull of a
//                point set, built once by hull/'s quickhull).
//
// Every shape carries an optional `margin` >= 0: the shape is then its
// Minkowski sum with a ball of that radius (a rounded box, a rounded hull...).
// The query layer never pushes rounding through GJK: a shape splits into a
// core (a point for spheres, a segment for capsules, the shape itself
// otherwise) and a radius added analytically (see minkowski.hpp).
//
// ConvexPolyhedron stores its vertices recentred on the hull's centroid and
// keeps the centroid as offset(): vertex(i) + offset() is the vertex in the
// frame of the input points. Support queries and tolerances therefore work
// with coordinates of the hull's own size, however far from the origin the
// input points were. Besides the half-edge mesh it keeps the vertex adjacency
// in compressed rows (neighbour indices of vertex i in
// neighbors[neighbor_offsets[i] .. neighbor_offsets[i+1])), derived from the
// half-edge rings, for the hill-climbing support.
//
// Invariants: every shape that passed validate() has finite, non-negative
// parameters of at most max_shape_size; a ConvexPolyhedron exists only if the hull was built (at least
// one vertex, all finite) and is never modified afterwards, so it can be
// shared between bodies and threads through std::shared_ptr<const ...>.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <hedra/hull/half_edge_mesh.hpp>
#include <hedra/hull/quickhull.hpp>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace hedra::collision {

enum class ShapeError {
  none,
  non_finite,       // a NaN or infinite parameter or point
  negative_size,    // a negative radius, half-length or half-extent
  negative_margin,  // margin < 0
  empty_points,     // a polyhedron built from no points
  out_of_range,     // a size or point set too large for double arithmetic (see validate())
  hull_failed,      // quickhull reported an error (message says which)
  null_polyhedron,  // a Polyhedron shape without its hull
};

const char* to_string(ShapeError error);

// The largest radius, half-length, half-extent or margin validate() accepts
// (the same bound as hull::max_input_extent for polyhedra): queries square
// and multiply sizes, which must not overflow a double.
constexpr double max_shape_size = 1e60;

struct ShapeValidation {
  ShapeError error = ShapeError::none;
  std::string message;  // empty when ok
  bool ok() const { return error == ShapeError::none; }
};

struct Sphere {
  double radius = 0.0;
  double margin = 0.0;
};

struct Box {
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();
  double margin = 0.0;
};

struct Capsule {
  double radius = 0.0;
  double half_length = 0.0;
  double margin = 0.0;
};

struct Cylinder {
  double radius = 0.0;
  double half_length = 0.0;
  double margin = 0.0;
};

struct Cone {
  double radius = 0.0;       // of the base disc at z = -half_length
  double half_length = 0.0;  // apex at z = +half_length
  double margin = 0.0;
};

// Named parameters for the factories below: each wraps one number and has
// an explicit constructor, so a size is always written with its name
// (`Radius{0.3}`), never as a bare number or an unnamed `{0.3}`.
struct Radius {
  explicit constexpr Radius(double v) : value(v) {}
  double value;
};
struct HalfLength {
  explicit constexpr HalfLength(double v) : value(v) {}
  double value;
};
struct HalfExtents {
  explicit HalfExtents(const Eigen::Vector3d& v) : value(v) {}
  HalfExtents(double x, double y, double z) : value(x, y, z) {}
  Eigen::Vector3d value;
};
struct Margin {
  explicit constexpr Margin(double v) : value(v) {}
  double value;
};

// Shapes whose meaning cannot be swapped silently: make_capsule(Radius{0.3},
// HalfLength{0.5}) is the capsule of radius 0.3, and the arguments in the
// other order do not compile. The aggregates (Capsule{radius, half_length,
// margin}) stay for code that names its fields; these say the same.
inline Sphere make_sphere(Radius r, Margin m = Margin{0.0}) { return {r.value, m.value}; }
inline Box make_box(const HalfExtents& h, Margin m = Margin{0.0}) { return {h.value, m.value}; }
inline Capsule make_capsule(Radius r, HalfLength h, Margin m = Margin{0.0}) { return {r.value, h.value, m.value}; }
inline Cylinder make_cylinder(Radius r, HalfLength h, Margin m = Margin{0.0}) { return {r.value, h.value, m.value}; }
inline Cone make_cone(Radius r, HalfLength h, Margin m = Margin{0.0}) { return {r.value, h.value, m.value}; }

class ConvexPolyhedron {
 public:
  struct BuildResult {
    std::shared_ptr<const ConvexPolyhedron> polyhedron;  // null unless ok()
    ShapeError error = ShapeError::none;
    std::string message;
    bool ok() const { return error == ShapeError::none; }
  };

  // The convex hull of `points` (quickhull; degenerate inputs give point,
  // segment or flat hulls, which are valid shapes).
  static BuildResult build(const std::vector<Eigen::Vector3d>& points, const hull::QuickhullOptions& options = {});

  // The hull's centroid in the frame of the input points (solid centroid,
  // area centroid when flat, vertex average for a point or segment).
  const Eigen::Vector3d& offset() const { return offset_; }
  std::size_t vertex_count() const { return vertices_.size(); }
  // Vertex i relative to offset().
  const Eigen::Vector3d& vertex(hull::Index i) const { return vertices_[i]; }
  const std::vector<Eigen::Vector3d>& vertices() const { return vertices_; }
  // Neighbours of vertex i along hull edges (empty for point and segment
  // hulls, whose meshes have no edges).
  const hull::Index* neighbors_begin(hull::Index i) const { return neighbors_.data() + neighbor_offsets_[i]; }
  const hull::Index* neighbors_end(hull::Index i) const { return neighbors_.data() + neighbor_offsets_[i + 1]; }
  // All rows back to back (row i from neighbor_offsets(i)); a position in
  // this array is an edge slot: vertex i to its neighbour there.
  const hull::Index* neighbors() const { return neighbors_.data(); }
  std::uint32_t neighbor_offset(hull::Index i) const { return neighbor_offsets_[i]; }
  // For the edge slot s (vertex u to w = neighbors()[s]): the part of w's
  // row a hill-climb that came from u still has to look at, in the row's
  // order, as two ranges of positions [first_begin, first_end) and
  // [second_begin, neighbor_offset(w + 1)). Left out: the run of w's row
  // around u made of u and neighbours of u (on a triangulated hull u and the
  // apexes of the two triangles on the edge). A climb steps from u to w only
  // when w is the best of u's row, so none of those can beat w (support.hpp).
  struct EntryRows {
    std::uint32_t first_begin;
    std::uint32_t first_end;
    std::uint32_t second_begin;
  };
  const EntryRows& entry_rows(std::size_t slot) const { return entry_rows_[slot]; }
  // The vertices again in blocks of four, each coordinate apart (the
  // layout of the vectorised support scan, support.hpp); the last block is
  // padded with copies of vertex 0, which never beat vertex 0 itself.
  struct alignas(32) VertexBlock {
    double x[4];
    double y[4];
    double z[4];
  };
  const std::vector<VertexBlock>& vertex_blocks() const { return blocks_; }
  // Start vertices for a hill-climb without a hint (large solid hulls
  // only, empty otherwise): the extreme vertices of kStartDirections
  // directions spread over the sphere, in the same blocks (padded with the
  // first), and their indices. A climb from the best of them walks a few
  // steps instead of across the hull.
  static constexpr std::size_t kStartDirections = 32;
  static constexpr std::size_t kStartMinVertices = 256;
  const std::vector<VertexBlock>& start_blocks() const { return start_blocks_; }
  hull::Index start_vertex(std::size_t position) const { return start_ids_[position]; }
  // The half-edge mesh, recentred like vertex() (same vertex indices).
  const hull::HalfEdgeMesh& mesh() const { return mesh_; }
  int dimension() const { return dimension_; }
  // max |vertex(i)|: the radius of a ball around offset() holding the hull.
  double bounding_radius() const { return bounding_radius_; }

 private:
  ConvexPolyhedron() = default;
  // vertex_blocks() and the start vertices, from vertices_.
  void build_blocks();
  // entry_rows_, from the neighbour rows.
  void build_entry_rows();

  Eigen::Vector3d offset_ = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> vertices_;
  std::vector<VertexBlock> blocks_;
  std::vector<VertexBlock> start_blocks_;
  std::vector<hull::Index> start_ids_;
  std::vector<std::uint32_t> neighbor_offsets_;  // vertex_count() + 1 entries
  std::vector<hull::Index> neighbors_;
  std::vector<EntryRows> entry_rows_;  // one per entry of neighbors_
  hull::HalfEdgeMesh mesh_;
  int dimension_ = 0;  // mesh_.dimension(), kept: the support mapping asks on every call
  double bounding_radius_ = 0.0;
};

struct Polyhedron {
  std::shared_ptr<const ConvexPolyhedron> hull;
  double margin = 0.0;
};

// A small closed set of shapes: queries dispatch once on it (std::visit) and
// run fully typed code inside.
using Shape = std::variant<Sphere, Box, Capsule, Cylinder, Cone, Polyhedron>;

ShapeValidation validate(const Sphere& s);
ShapeValidation validate(const Box& s);
ShapeValidation validate(const Capsule& s);
ShapeValidation validate(const Cylinder& s);
ShapeValidation validate(const Cone& s);
ShapeValidation validate(const Polyhedron& s);
ShapeValidation validate(const Shape& s);
// validate(s).ok() without building a message: what queries check on every
// call (no allocation, a few comparisons).
bool is_valid(const Shape& s);
// is_valid(s), and bounding_radius(s) into `radius` (whatever the answer),
// in one dispatch: what queries check first.
bool is_valid(const Shape& s, double& radius);

// Radius of a ball around the local origin holding the whole shape (margin
// included). For a polyhedron the ball is centred on offset() instead, the
// point queries work around.
double bounding_radius(const Sphere& s);
double bounding_radius(const Box& s);
double bounding_radius(const Capsule& s);
double bounding_radius(const Cylinder& s);
double bounding_radius(const Cone& s);
double bounding_radius(const Polyhedron& s);
double bounding_radius(const Shape& s);

}  // namespace hedra::collision
