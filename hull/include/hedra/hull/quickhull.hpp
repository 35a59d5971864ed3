// Quickhull in 3D, writing a half-edge convex polyhedron with convex polygon
// faces (Barber, Dobkin, Huhdanpaa 1996; face merging during construction as
// in Gregorius, "Implementing Quickhull", GDC 2014).
//
// Outline:
//   1. Reject empty or non-finite input (the error names the first bad point),
//      and input spanning more than max_input_extent (1e60) along an axis:
//      normals are cross products of coordinate differences and their squared
//      lengths multiply four of them, which must not overflow a double (found
//      by fuzzing: a span of 1e98 gave a zero normal and a wrong hull). For
//      the same reason a widest span below min_input_extent (1e-60) that is
//      not zero is rejected too: those products underflow to zero (found by
//      fuzzing: points 1e-154 apart read as a segment, a corner left out).
//      All points equal (span 0) is a point hull, as always.
//   2. Recentre the points on their bounding-box centre and derive the
//      tolerance from the recentred extent:
//        eps = 3 * DBL_EPSILON * (max|x| + max|y| + max|z|),
//      so that coordinates far from the origin coarsen nothing.
//   3. Initial simplex from extreme points: the farthest pair of the six
//      axis-extreme points, the farthest point from their line, the farthest
//      point from that plane. Whenever one of these spans is <= eps the input
//      is degenerate and the hull is a point, a segment, or a flat convex
//      polygon (a 2D hull in the best-fit plane, stored as two back-to-back
//      faces).
//   4. Every point goes to the conflict list of a face it lies more than eps
//      in front of (the farthest such face for the initial simplex, the first
//      one afterwards); points in front of no face are inside and dropped.
//   5. Repeatedly take the farthest conflict point of a face (the eye), find
//      the faces it sees by a depth-first walk over the half-edges, whose
//      border is the horizon, replace them by a cone of triangles from the
//      horizon to the eye, merge each new face with any neighbour it is not
//      clearly convex with (centroid of either face less than eps behind the
//      other's plane), repair the topology the merge leaves (redundant
//      vertices of degree two, swallowed triangles), and hand the orphaned
//      conflict points of the removed faces to the new faces.
//      A third pass absorbs, across the edge leading in, any face that makes
//      a merged polygon turn outward at a vertex (nearly coplanar faces meeting
//      there). Planes come from hull::polygon_plane (Newell, corrected along
//      the longest edge so that slivers keep their vertices on the plane).
//   6. Compact the working structure into a HalfEdgeMesh whose vertices are
//      exactly input points (QuickhullResult::input_index maps them back).
//
// Self-check and retry: each result is checked in O(E) (faces planar and
// edges convex within 4 eps, the faces touched by each iteration linked
// consistently). Input that defeats eps (clusters of near-duplicates, slabs a
// few eps thick that flatten while merging) fails the check; the build then
// restarts with eps eightfold larger, up to a millionth of the extent, so
// the answer is a valid hull at a stated tolerance, never a broken one.
//
// Invariants kept between iterations: the working structure is a closed
// 2-manifold; every edge is convex within eps; every conflict point is more
// than eps in front of its face. Each iteration consumes one point for good,
// so the loop runs at most n times; the cap is still checked and reported.
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
