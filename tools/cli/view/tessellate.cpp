// Tessellation of collision shapes for `hedra view` (see tessellate.hpp).
#include "cli/view/tessellate.hpp"

#include <algorithm>
#include <cmath>
#include <hedra/hull/quickhull.hpp>
#include <type_traits>
#include <vector>

namespace hedra::tool::view {

namespace {

constexpr double kPi = 3.14159265358979323846;

// `count` points on the circle of `radius` at height z, starting on +x.
void add_circle(std::vector<Eigen::Vector3d>& points, double radius, double z, int count) {
  for (int i = 0; i < count; ++i) {
    const double angle = 2.0 * kPi * i / count;
    points.emplace_back(radius * std::cos(angle), radius * std::sin(angle), z);
  }
}

// A latitude-longitude grid on the sphere of `radius` around the origin:
// both poles and segments/2 - 1 rings of `segments` points. With an even
// `segments` divisible by 4 it contains the six axis directions, so the
// flat faces of a rounded box come out exactly.
std::vector<Eigen::Vector3d> sphere_grid(double radius, int segments) {
  std::vector<Eigen::Vector3d> points;
  const int rings = segments / 2;
  points.emplace_back(0.0, 0.0, radius);
  for (int ring = 1; ring < rings; ++ring) {
    const double polar = kPi * ring / rings;
    add_circle(points, radius * std::sin(polar), radius * std::cos(polar), segments);
  }
  points.emplace_back(0.0, 0.0, -radius);
  return points;
}

// Points of the core (the shape without its rounding) in the shape's local
// frame, and the radius the core is rounded by (margin included).
struct Core {
  std::vector<Eigen::Vector3d> points;
  double radius = 0.0;
};

Core core_points(const collision::Sphere& s, int) { return {{Eigen::Vector3d::Zero()}, s.radius + s.margin}; }

Core core_points(const collision::Box& s, int) {
  Core core{{}, s.margin};
  for (int corner = 0; corner < 8; ++corner) {
    core.points.emplace_back((corner & 1 ? 1 : -1) * s.half_extents.x(), (corner & 2 ? 1 : -1) * s.half_extents.y(),
                             (corner & 4 ? 1 : -1) * s.half_extents.z());
  }
  return core;
}

Core core_points(const collision::Capsule& s, int) {
  return {{Eigen::Vector3d(0, 0, -s.half_length), Eigen::Vector3d(0, 0, s.half_length)}, s.radius + s.margin};
}

Core core_points(const collision::Cylinder& s, int segments) {
  Core core{{}, s.margin};
  add_circle(core.points, s.radius, -s.half_length, segments);
  add_circle(core.points, s.radius, s.half_length, segments);
  return core;
}

Core core_points(const collision::Cone& s, int segments) {
  Core core{{Eigen::Vector3d(0, 0, s.half_length)}, s.margin};
  add_circle(core.points, s.radius, -s.half_length, segments);
  return core;
}

Core core_points(const collision::Polyhedron& s, int) {
  Core core{{}, s.margin};
  core.points.reserve(s.hull->vertex_count());
  for (const Eigen::Vector3d& v : s.hull->vertices()) core.points.push_back(v + s.hull->offset());
  return core;
}

// The hull of `points` (local frame) as a posed polygon mesh.
bool hull_mesh(const std::vector<Eigen::Vector3d>& points, const collision::Pose& pose, PolygonMesh& out,
               std::string& error) {
  const hull::QuickhullResult result = hull::build_hull(points);
  if (!result.ok()) {
    error = std::string("cannot tessellate (") + hull::to_string(result.status) + "): " + result.error;
    return false;
  }
  out = polygon_mesh(result.mesh, [&](const Eigen::Vector3d& x) { return pose.apply(x); });
  return true;
}

// The shape drawn whole: its core's points swept by the rounding radius.
template <class S>
bool whole_mesh(const S& shape, const collision::Pose& pose, const TessellationOptions& options, PolygonMesh& out,
                std::string& error) {
  if constexpr (std::is_same_v<S, collision::Polyhedron>) {
    if (shape.margin == 0.0) {
      const Eigen::Vector3d offset = shape.hull->offset();
      out = polygon_mesh(shape.hull->mesh(), [&](const Eigen::Vector3d& x) { return pose.apply(x + offset); });
      return true;
    }
  }
  const Core core = core_points(shape, options.segments);
  if (core.radius == 0.0) return hull_mesh(core.points, pose, out, error);
  // A sphere or capsule is curved itself: give it the finer grid.
  const bool curved = std::is_same_v<S, collision::Sphere> || std::is_same_v<S, collision::Capsule>;
  const int ball_segments = curved ? options.segments : options.margin_segments;
  const std::vector<Eigen::Vector3d> ball = sphere_grid(core.radius, ball_segments);
  std::vector<Eigen::Vector3d> swept;
  swept.reserve(core.points.size() * ball.size());
  for (const Eigen::Vector3d& p : core.points) {
    for (const Eigen::Vector3d& q : ball) swept.push_back(p + q);
  }
  return hull_mesh(swept, pose, out, error);
}

template <class S>
S without_margin(S shape) {
  shape.margin = 0.0;
  return shape;
}

// Rounds a requested segment count up to a multiple of 4 (so the grids
// contain the axis directions) within [4, 256].
int grid_segments(int requested) {
  const int clamped = std::clamp(requested, 4, 256);
  return (clamped + 3) / 4 * 4;
}

}  // namespace

const char* shape_kind(const collision::Shape& shape) {
  struct Kind {
    const char* operator()(const collision::Sphere&) const { return "sphere"; }
    const char* operator()(const collision::Box&) const { return "box"; }
    const char* operator()(const collision::Capsule&) const { return "capsule"; }
    const char* operator()(const collision::Cylinder&) const { return "cylinder"; }
    const char* operator()(const collision::Cone&) const { return "cone"; }
    const char* operator()(const collision::Polyhedron&) const { return "hull"; }
  };
  return std::visit(Kind{}, shape);
}

TessellatedShape tessellate(const collision::Shape& shape, const collision::Pose& pose,
                            const TessellationOptions& requested) {
  TessellatedShape out;
  const collision::ShapeValidation validation = collision::validate(shape);
  if (!validation.ok()) {
    out.error = validation.message;
    return out;
  }
  if (!pose.finite()) {
    out.error = "the pose has a non-finite entry";
    return out;
  }
  TessellationOptions options;
  options.segments = grid_segments(requested.segments);
  options.margin_segments = grid_segments(requested.margin_segments);
  std::visit(
      [&](const auto& s) {
        if (!whole_mesh(s, pose, options, out.mesh, out.error)) return;
        if (s.margin > 0.0) whole_mesh(without_margin(s), pose, options, out.core, out.error);
      },
      shape);
  if (!out.ok()) out.mesh = out.core = PolygonMesh{};
  return out;
}

bool make_view_body(const std::string& name, const collision::Shape& shape, const collision::Pose& pose, ViewBody& body,
                    std::string& error, const TessellationOptions& options) {
  TessellatedShape tessellated = tessellate(shape, pose, options);
  if (!tessellated.ok()) {
    error = "body " + name + ": " + tessellated.error;
    return false;
  }
  body.name = name;
  body.shape = shape_kind(shape);
  body.margin = std::visit([](const auto& s) { return s.margin; }, shape);
  body.mesh = std::move(tessellated.mesh);
  body.core = std::move(tessellated.core);
  return true;
}

}  // namespace hedra::tool::view
