// Quickhull in 3D into a half-edge convex polyhedron with convex polygon
// faces (Barber, Dobkin, Huhdanpaa 1996; merging during construction as in
// Gregorius, "Implementing Quickhull", GDC 2014). Input is checked (finite,
// spans within [min_input_extent, max_input_extent]) and recentred; eps =
// 3 DBL_EPSILON (max|x| + max|y| + max|z|) of the recentred extent. A simplex
// from the extreme points (or a point, segment or flat polygon when the input
// spans no volume within eps), then per eye: horizon, cone, merges of faces
// not clearly convex, orphans reassigned; points merging left outside are put
// back. Invariants between iterations: a closed 2-manifold, every edge convex
// within eps, a conflict point joins a face only when more than eps in front
// of it (a merge may tilt the plane later: the eye is checked again), the
// loop capped and the cap reported. Each result is checked in O(E); a
// failure retries with eps eightfold larger (up to 1e-6 of the extent), so
// the answer is a valid hull at a stated tolerance, never a broken one.
// The step-by-step outline: docs/design.md (hull).
#pragma once

#include <cstddef>
#include <hedra/hull/half_edge_mesh.hpp>
#include <memory>
#include <string>
#include <vector>

namespace hedra::hull {

enum class QuickhullStatus {
  ok,
  empty_input,         // no points at all
  non_finite_input,    // a NaN or infinite coordinate; error names the point
  out_of_range_input,  // the points span more than max_input_extent along an axis, or
                       // their widest span is not zero but below min_input_extent
  iteration_limit,     // the iteration cap was hit (the mesh is the hull so far)
  topology_failure,    // an internal consistency check failed (never expected)
};

const char* to_string(QuickhullStatus status);

// The largest extent (max - min of a coordinate) quickhull accepts: products
// of up to five coordinate differences stay below 1e300.
constexpr double max_input_extent = 1e60;
// The smallest widest span (over the three axes) quickhull accepts, unless
// every point is the same: products of up to five coordinate differences
// stay above 1e-300, clear of the subnormal range where a double loses its
// precision.
constexpr double min_input_extent = 1e-60;

struct QuickhullOptions {
  // Points within this distance of a face plane count as on it. 0 (the
  // default) derives it from the input as described above.
  double tolerance = 0.0;
  // Cap on the number of points added to the hull; 0 means the number of
  // input points (the most the algorithm can ever need).
  std::size_t max_iterations = 0;
};

struct QuickhullResult {
  QuickhullStatus status = QuickhullStatus::ok;
  std::string error;               // human-readable reason when status != ok
  HalfEdgeMesh mesh;               // the hull; vertex positions are input points
  std::vector<Index> input_index;  // mesh vertex -> index of the input point
  // The eps the build's decisions used (after any retries). The output holds
  // to mesh.tolerance() = 8 eps + 12 DBL_EPSILON per unit of |coordinate|
  // (what representing planes in world coordinates costs): faces are planar
  // and edges convex within it, and every input point lies within it of the
  // hull. Merging lets points drift outside by a few eps: the property tests
  // measure it over thousands of clouds.
  double tolerance = 0.0;
  int dimension = -1;          // 0 point, 1 segment, 2 polygon, 3 solid
  std::size_t iterations = 0;  // points added after the initial simplex

  bool ok() const { return status == QuickhullStatus::ok; }
};

// Builds hulls, keeping its working memory between calls so that repeated
// builds allocate little. Not thread-safe; use one builder per thread.
class QuickhullBuilder {
 public:
  QuickhullBuilder();
  ~QuickhullBuilder();
  QuickhullBuilder(QuickhullBuilder&&) noexcept;
  QuickhullBuilder& operator=(QuickhullBuilder&&) noexcept;

  QuickhullResult build(const Eigen::Vector3d* points, std::size_t count, const QuickhullOptions& options = {});
  QuickhullResult build(const std::vector<Eigen::Vector3d>& points, const QuickhullOptions& options = {}) {
    return build(points.data(), points.size(), options);
  }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One-shot convenience.
QuickhullResult build_hull(const std::vector<Eigen::Vector3d>& points, const QuickhullOptions& options = {});

// Largest distance of any point in front of any face plane of `mesh` (0 when
// all are inside or on it): for a solid, max over points and faces of the
// signed plane distance (equal to the Euclidean distance for points outside
// near a face, a lower bound near edges and corners); for a flat hull, the
// largest of |distance to the plane| and the distances outside its edges; for
// a point or segment hull, the Euclidean distance to it.
double max_outside_distance(const HalfEdgeMesh& mesh, const std::vector<Eigen::Vector3d>& points);

}  // namespace hedra::hull
