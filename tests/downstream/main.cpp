// Downstream consumer: the hull of a unit cube's 8 corners through the
// installed (or add_subdirectory'd) hedra::hull must be a valid mesh with 8
// vertices and 6 quadrilateral faces. Exit 0 only then.
#include <cstdio>
#include <hedra/hull/quickhull.hpp>
#include <vector>

int main() {
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
