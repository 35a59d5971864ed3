// Shape validation and the ConvexPolyhedron builder: quickhull over the input
// points, then recentring on the hull's centroid (vertices and face planes
// shifted together, so the mesh keeps every invariant) and the vertex
// adjacency in compressed rows for the hill-climbing support.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <hedra/collision/shapes.hpp>
#include <hedra/hull/mass.hpp>

namespace hedra::collision {

const char* to_string(ShapeError error) {
  switch (error) {
    case ShapeError::none:
      return "none";
    case ShapeError::non_finite:
      return "non_finite";
    case ShapeError::negative_size:
      return "negative_size";
    case ShapeError::negative_margin:
      return "negative_margin";
    case ShapeError::empty_points:
      return "empty_points";
    case ShapeError::out_of_range:
      return "out_of_range";
    case ShapeError::hull_failed:
      return "hull_failed";
    case ShapeError::null_polyhedron:
      return "null_polyhedron";
  }
  return "unknown";
}

namespace {

ShapeValidation fail(ShapeError error, const char* what, double value) {
  char buffer[160];
  std::snprintf(buffer, sizeof buffer, "%s = %.17g", what, value);
  return {error, buffer};
}

// Checks one size parameter; `what` names it in the message.
bool check_size(double value, const char* what, ShapeValidation& out) {
  if (!std::isfinite(value)) {
    out = fail(ShapeError::non_finite, what, value);
    return false;
  }
  if (value < 0.0) {
    out = fail(ShapeError::negative_size, what, value);
    return false;
  }
  if (value > max_shape_size) {
    out = fail(ShapeError::out_of_range, what, value);
    out.message += " is larger than max_shape_size (1e60)";
    return false;
  }
  return true;
}

bool check_margin(double margin, ShapeValidation& out) {
  if (!std::isfinite(margin)) {
    out = fail(ShapeError::non_finite, "margin", margin);
    return false;
  }
  if (margin < 0.0) {
    out = fail(ShapeError::negative_margin, "margin", margin);
    return false;
  }
  if (margin > max_shape_size) {
    out = fail(ShapeError::out_of_range, "margin", margin);
    out.message += " is larger than max_shape_size (1e60)";
    return false;
  }
  return true;
}

}  // namespace

ShapeValidation validate(const Sphere& s) {
  ShapeValidation out;
  if (check_size(s.radius, "sphere radius", out)) check_margin(s.margin, out);
  return out;
}

ShapeValidation validate(const Box& s) {
  ShapeValidation out;
  if (check_size(s.half_extents.x(), "box half_extents.x", out) &&
      check_size(s.half_extents.y(), "box half_extents.y", out) &&
      check_size(s.half_extents.z(), "box half_extents.z", out))
    check_margin(s.margin, out);
  return out;
}

ShapeValidation validate(const Capsule& s) {
  ShapeValidation out;
  if (check_size(s.half_length, "capsule half_length", out) && check_size(s.radius, "capsule radius", out))
    check_margin(s.margin, out);
  return out;
}

ShapeValidation validate(const Cylinder& s) {
  ShapeValidation out;
  if (check_size(s.half_length, "cylinder half_length", out) && check_size(s.radius, "cylinder radius", out))
    check_margin(s.margin, out);
  return out;
}

ShapeValidation validate(const Cone& s) {
  ShapeValidation out;
  if (check_size(s.half_length, "cone half_length", out) && check_size(s.radius, "cone radius", out))
    check_margin(s.margin, out);
  return out;
}

ShapeValidation validate(const Polyhedron& s) {
  ShapeValidation out;
  if (!s.hull) return {ShapeError::null_polyhedron, "polyhedron without a hull"};
  check_margin(s.margin, out);
  return out;
}

ShapeValidation validate(const Shape& s) {
  return std::visit([](const auto& shape) { return validate(shape); }, s);
}

namespace {

// check_size() and check_margin() as one comparison: NaN and infinities fail.
bool in_range(double value) { return value >= 0.0 && value <= max_shape_size; }

bool is_valid_shape(const Sphere& s) { return in_range(s.radius) && in_range(s.margin); }
bool is_valid_shape(const Box& s) {
  return in_range(s.half_extents.x()) && in_range(s.half_extents.y()) && in_range(s.half_extents.z()) &&
         in_range(s.margin);
}
bool is_valid_shape(const Capsule& s) { return in_range(s.half_length) && in_range(s.radius) && in_range(s.margin); }
bool is_valid_shape(const Cylinder& s) { return in_range(s.half_length) && in_range(s.radius) && in_range(s.margin); }
bool is_valid_shape(const Cone& s) { return in_range(s.half_length) && in_range(s.radius) && in_range(s.margin); }
bool is_valid_shape(const Polyhedron& s) { return s.hull != nullptr && in_range(s.margin); }

}  // namespace

bool is_valid(const Shape& s) {
  return std::visit([](const auto& shape) { return is_valid_shape(shape); }, s);
}

bool is_valid(const Shape& s, double& radius) {
  return std::visit(
      [&radius](const auto& shape) {
        radius = bounding_radius(shape);
        return is_valid_shape(shape);
      },
      s);
}

double bounding_radius(const Sphere& s) { return s.radius + s.margin; }
double bounding_radius(const Box& s) { return s.half_extents.norm() + s.margin; }
double bounding_radius(const Capsule& s) { return s.half_length + s.radius + s.margin; }
double bounding_radius(const Cylinder& s) { return std::hypot(s.radius, s.half_length) + s.margin; }
double bounding_radius(const Cone& s) { return std::hypot(s.radius, s.half_length) + s.margin; }
double bounding_radius(const Polyhedron& s) { return (s.hull ? s.hull->bounding_radius() : 0.0) + s.margin; }
double bounding_radius(const Shape& s) {
  return std::visit([](const auto& shape) { return bounding_radius(shape); }, s);
}

namespace {

// Points `ids[0 .. count)` of `points` into blocks of four, the last padded
// with points[pad].
void append_blocks(const std::vector<Eigen::Vector3d>& points, const hull::Index* ids, std::size_t count,
                   hull::Index pad, std::vector<ConvexPolyhedron::VertexBlock>& out) {
  for (std::size_t i = 0; i < count || i % 4 != 0; ++i) {
    if (i % 4 == 0) out.emplace_back();
    const Eigen::Vector3d& x = points[i < count ? ids[i] : pad];
    out.back().x[i % 4] = x.x();
    out.back().y[i % 4] = x.y();
    out.back().z[i % 4] = x.z();
  }
}

}  // namespace

void ConvexPolyhedron::build_blocks() {
  const std::size_t n = vertices_.size();
  std::vector<hull::Index> all(n);
  for (std::size_t i = 0; i < n; ++i) all[i] = static_cast<hull::Index>(i);
  blocks_.clear();
  append_blocks(vertices_, all.data(), n, 0, blocks_);
  start_blocks_.clear();
  start_ids_.clear();
  if (n < kStartMinVertices || dimension_ < 3) return;
  // Directions on a Fibonacci spiral: z evenly spaced, longitude turning by
  // the golden angle.
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (std::size_t k = 0; k < kStartDirections; ++k) {
    const double z = 1.0 - (2.0 * static_cast<double>(k) + 1.0) / static_cast<double>(kStartDirections);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden * static_cast<double>(k);
    const Eigen::Vector3d d(r * std::cos(phi), r * std::sin(phi), z);
    hull::Index best = 0;
    for (std::size_t i = 1; i < n; ++i)
      if (d.dot(vertices_[i]) > d.dot(vertices_[best])) best = static_cast<hull::Index>(i);
    start_ids_.push_back(best);
  }
  append_blocks(vertices_, start_ids_.data(), start_ids_.size(), start_ids_[0], start_blocks_);
}

void ConvexPolyhedron::build_entry_rows() {
  const std::size_t n = vertices_.size();
  entry_rows_.assign(neighbors_.size(), EntryRows{0, 0, 0});
  // mark[x] == u + 1: x is u or one of u's neighbours.
  std::vector<std::size_t> mark(n, 0);
  for (hull::Index u = 0; u < n; ++u) {
    const std::uint32_t begin = neighbor_offsets_[u], end = neighbor_offsets_[u + 1];
    mark[u] = u + 1;
    for (std::uint32_t s = begin; s < end; ++s) mark[neighbors_[s]] = u + 1;
    for (std::uint32_t s = begin; s < end; ++s) {
      const hull::Index w = neighbors_[s];
      const std::uint32_t row = neighbor_offsets_[w];
      const std::ptrdiff_t k = static_cast<std::ptrdiff_t>(neighbor_offsets_[w + 1] - row);
      const hull::Index* const x = neighbors_.data() + row;
      std::ptrdiff_t r = 0;
      while (r < k && x[r] != u) ++r;
      if (r == k) {  // u missing from w's row (not on a valid mesh): look at all of it
        entry_rows_[s] = {row, row + static_cast<std::uint32_t>(k), row + static_cast<std::uint32_t>(k)};
        continue;
      }
      // The run around position r of u and u's neighbours, at most the row.
      const auto at = [&](std::ptrdiff_t i) { return x[((i % k) + k) % k]; };
      std::ptrdiff_t lo = r, count = 1;
      while (count < k && mark[at(lo - 1)] == u + 1) --lo, ++count;
      while (count < k && mark[at(lo + count)] == u + 1) ++count;
      const std::ptrdiff_t start = ((lo % k) + k) % k;
      const auto pos = [row](std::ptrdiff_t i) { return row + static_cast<std::uint32_t>(i); };
      if (count == k) {
        entry_rows_[s] = {pos(k), pos(k), pos(k)};
      } else if (start + count <= k) {
        entry_rows_[s] = {pos(0), pos(start), pos(start + count)};
      } else {  // the run wraps past the row's end: what is left is one range
        entry_rows_[s] = {pos(start + count - k), pos(start), pos(k)};
      }
    }
  }
}

ConvexPolyhedron::BuildResult ConvexPolyhedron::build(const std::vector<Eigen::Vector3d>& points,
                                                      const hull::QuickhullOptions& options) {
  BuildResult result;
  if (points.empty()) {
    result.error = ShapeError::empty_points;
    result.message = "no points";
    return result;
  }
  hull::QuickhullResult built = hull::build_hull(points, options);
  if (!built.ok()) {
    // quickhull names the first non-finite point itself.
    result.error = built.status == hull::QuickhullStatus::non_finite_input     ? ShapeError::non_finite
                   : built.status == hull::QuickhullStatus::out_of_range_input ? ShapeError::out_of_range
                                                                               : ShapeError::hull_failed;
    result.message = std::string(hull::to_string(built.status)) + ": " + built.error;
    return result;
  }

  std::shared_ptr<ConvexPolyhedron> poly(new ConvexPolyhedron());
  poly->mesh_ = std::move(built.mesh);
  hull::HalfEdgeMesh& mesh = poly->mesh_;
  const std::size_t n = mesh.vertex_count();

  // Recentring moves positions and plane offsets together
  // (n.(x - c) = d - n.c), which keeps every mesh invariant.
  auto shift = [&mesh](const Eigen::Vector3d& c) {
    for (hull::Vertex& v : mesh.vertices) v.position -= c;
    for (hull::Face& f : mesh.faces) f.plane.offset -= f.plane.normal.dot(c);
  };
  // First on the vertex average, so that the centroid integrals below run on
  // coordinates of the hull's own size (input far from the origin would
  // otherwise cost the centroid the digits of its distance); then on the
  // centroid: of the solid, or of the polygon's area. A point or a segment
  // has no area and keeps the vertex average.
  Eigen::Vector3d average = Eigen::Vector3d::Zero();
  for (const hull::Vertex& v : mesh.vertices) average += v.position;
  average /= static_cast<double>(n);
  shift(average);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  if (mesh.dimension() >= 2) {
    const Eigen::Vector3d c = hull::mass_properties(mesh).centroid;
    if (c.allFinite()) centre = c;
  }
  shift(centre);
  poly->offset_ = average + centre;

  poly->vertices_.reserve(n);
  poly->neighbor_offsets_.assign(n + 1, 0);
  double radius = 0.0;
  for (hull::Index v = 0; v < n; ++v) {
    poly->vertices_.push_back(mesh.position(v));
    radius = std::max(radius, mesh.position(v).norm());
  }
  poly->bounding_radius_ = radius;
  poly->dimension_ = mesh.dimension();
  // Point and segment hulls have no edges: empty rows.
  poly->neighbors_.reserve(mesh.half_edge_count());
  for (hull::Index v = 0; v < n; ++v) {
    if (mesh.vertices[v].edge != hull::kInvalidIndex) {
      for (hull::Index w : mesh.vertex_neighbors(v)) poly->neighbors_.push_back(w);
    }
    poly->neighbor_offsets_[v + 1] = static_cast<std::uint32_t>(poly->neighbors_.size());
  }
  poly->build_blocks();
  poly->build_entry_rows();
  result.polyhedron = std::move(poly);
  return result;
}

}  // namespace hedra::collision
