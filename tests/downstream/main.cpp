// Downstream consumer, built through find_package and add_subdirectory:
//   * hedra::hull: the hull of a unit cube's 8 corners must be a valid mesh
//     with 8 vertices and 6 quadrilateral faces;
//   * hedra::collision: a box and a convex hull 0.5 apart, then pushed 0.25
//     into each other: distance() and penetration() must say so.
// The part between the README markers is shown verbatim in the README's
// Embedding section. Exit 0 only if every check passes.
#include <cmath>
#include <cstdio>
#include <hedra/collision/query.hpp>
#include <hedra/hull/quickhull.hpp>
#include <vector>

namespace {

int check_hull() {
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i) corners.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const hedra::hull::QuickhullResult result = hedra::hull::build_hull(corners);
  if (!result.ok()) {
    std::fprintf(stderr, "build_hull failed (%s): %s\n", hedra::hull::to_string(result.status), result.error.c_str());
    return 1;
  }
  const hedra::hull::ValidationReport report = result.mesh.validate();
  if (!report.ok()) {
    std::fprintf(stderr, "invalid hull:\n%s\n", report.to_string().c_str());
    return 1;
  }
  if (result.mesh.vertex_count() != 8 || result.mesh.face_count() != 6) {
    std::fprintf(stderr, "expected 8 vertices and 6 faces, got %zu and %zu\n", result.mesh.vertex_count(),
                 result.mesh.face_count());
    return 1;
  }
  std::printf("hedra consumer: cube hull has %zu vertices, %zu faces\n", result.mesh.vertex_count(),
              result.mesh.face_count());
  return 0;
}

int check_collision() {
  // README example begin
  using namespace hedra::collision;
  // A convex hull (an octahedron of radius 1, shared by every body that uses it).
  const auto built = ConvexPolyhedron::build({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}});
  if (!built.ok()) {
    std::fprintf(stderr, "hull: %s\n", built.message.c_str());
    return 1;
  }
  const Shape hull = Polyhedron{built.polyhedron};
  const Shape box = Box{{0.5, 0.5, 0.5}};  // half extents

  // The box at the origin, the octahedron's tip 0.5 above its top face.
  const DistanceResult d = distance(box, Pose::identity(), hull, Pose::from_translation({0, 0, 2}));
  std::printf("distance %.6f, normal (%g, %g, %g)\n", d.distance, d.normal.x(), d.normal.y(), d.normal.z());

  // Pushed 0.25 into the box: a negative signed distance, the depth.
  const PenetrationResult p = penetration(box, Pose::identity(), hull, Pose::from_translation({0, 0, 1.25}));
  std::printf("signed distance %.6f, normal (%g, %g, %g)\n", p.distance, p.normal.x(), p.normal.y(), p.normal.z());
  // README example end

  const bool distance_ok = d.status == Status::ok && !d.intersecting && std::abs(d.distance - 0.5) < 1e-12 &&
                           (d.normal - Eigen::Vector3d::UnitZ()).norm() < 1e-9;
  const bool penetration_ok = p.status == Status::ok && p.intersecting && std::abs(p.distance + 0.25) < 1e-12 &&
                              (p.normal - Eigen::Vector3d::UnitZ()).norm() < 1e-9;
  if (!distance_ok || !penetration_ok) {
    std::fprintf(stderr, "unexpected answers: distance %s %.17g, penetration %s %.17g\n", to_string(d.status),
                 d.distance, to_string(p.status), p.distance);
    return 1;
  }
  return 0;
}

}  // namespace

int main() { return check_hull() + check_collision() != 0 ? 1 : 0; }
