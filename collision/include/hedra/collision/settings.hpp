// The plain settings and per-pair state of the queries (query.hpp), apart
// from the algorithms that read them (gjk.hpp, epa.hpp), so that an embedder
// including query.hpp compiles no GJK or EPA template.
#pragma once

#include <Eigen/Core>
#include <hedra/hull/half_edge_mesh.hpp>

namespace hedra::collision {

struct GjkSettings {
  int max_iterations = 128;
  // The loop stops once the certified distance error is below
  // max(relative_tolerance * distance, absolute_tolerance * scale), scale
  // being the shapes' size (bounding radius).
  double relative_tolerance = 1e-10;
  double absolute_tolerance = 1e-10;
};

// Per-pair state the caller may keep between queries (frames: A's core frame,
// so it stays valid while the pair moves rigidly).
struct GjkCache {
  bool valid = false;
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();  // last v = point_a - point_b
  hull::Index hint_a = 0;                          // last support vertices of
  hull::Index hint_b = 0;                          // polyhedra (climb starts)
};

struct EpaSettings {
  int max_iterations = 128;
  // Stop once h(n) - d <= max(relative_tolerance * d, absolute_tolerance *
  // scale), scale being the shapes' size.
  double relative_tolerance = 1e-10;
  double absolute_tolerance = 1e-10;
  // Extents of D below flat_tolerance * scale count as zero (D is flat).
  double flat_tolerance = 1e-10;
};

}  // namespace hedra::collision
