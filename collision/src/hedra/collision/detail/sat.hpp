// Separating-axis test (SAT) between two convex polyhedra on the half-edge
// structure, after Gregorius, "The Separating Axis Test between Convex
// Polyhedra" (GDC 2013) and "Physics for Game Programmers: Robust Contact
// Creation" (GDC 2015).
//
// Frame: everything runs in A's core frame. B is placed there by the
// relative pose (minkowski.hpp: R = R_a^T R_b, t), so world coordinates of
// 1e6 cost nothing; B's vertices are transformed on the fly, never copied.
//
// Candidate axes and their separations (s > 0: a gap, s < 0: an overlap):
//   * face of A with plane (n, d): s = n . s_B(-n) - d, s_B the support
//     point of B (hill-climbing above the crossover, analytic for boxes);
//   * face of B, the same with the roles exchanged (computed in B's frame);
//   * edge pair (e_A, e_B): only when the pair builds a face of the Minkowski
//     difference, i.e. when the Gauss-map arcs of e_A (between its two face
//     normals a, b) and of e_B negated (-c, -d) cross on the unit sphere:
//         (c . (b x a)) (d . (b x a)) < 0,  (a . (d x c)) (b . (d x c)) < 0,
//         (c . (b x a)) (b . (d x c)) > 0
//     (the four dot products; b x a points along -e_A and d x c along -e_B,
//     so the negated edge vectors stand in for the cross products: no cross
//     product of two nearly equal normals, whose rounding would decide the
//     signs). The axis is N = e_A x e_B / |e_A x e_B| turned toward the
//     point where the two arcs cross (N . (a + b + c + d) >= 0: that point
//     is a non-negative combination of a, b and of c, d); only when both
//     arcs are half circles (two flat shapes, a + b + c + d is rounding) is
//     it turned away from A's centroid (the core origin), N . p_A >= 0.
//     s = N . (p_B - p_A). Nearly parallel edges, |e_A x e_B| <
//     parallel_tolerance |e_A| |e_B|, are skipped: their axis is
//     ill-conditioned and a face axis then nearly coincides with it.
// The largest separation over all candidates is the SAT separation: > 0
// proves a gap (a lower bound on the distance; exact when the closest
// features are a face and a vertex or face); <= 0 means overlap and its
// negation is the penetration depth (exact: the minimum translation is along
// one of these axes).
//
// Cost: faces of A x support in B + faces of B x support in A + the edge
// pairs of A x B through the Gauss-map test (most pairs fail the first two
// dot products). Early exit: as soon as an axis separates by more than
// `early_out` (the caller's speculative distance), the rest is skipped.
//
// Two boxes: the edge pairs are the 3 x 3 pairs of axis directions, each
// measured in closed form (|N . t| minus both boxes' projected radii, the
// classic OBB test, N turned toward B's centre), and the edges realising the chosen axis are the
// boxes' support edges along it. For overlapping boxes the largest of these
// 15 separations is the exact depth, like the Gauss-map version's.
//
// Degenerate polytopes (points, segments, flat polygons) are not for this
// test: callers check dimension() == 3.
#pragma once

#include <Eigen/Core>
#include <array>
#include <hedra/collision/detail/minkowski.hpp>
#include <hedra/collision/detail/support.hpp>
#include <hedra/collision/manifold.hpp>  // SatAxisKind
#include <hedra/collision/shapes.hpp>
#include <hedra/hull/half_edge_mesh.hpp>
#include <limits>

namespace hedra::collision {

// The topology of a box shared by every Box: vertex i is
// (+-1, +-1, +-1) with bit k of i set for + along axis k; faces are the six
// axis planes. Built once (on first use, thread-safe), never modified.
const hull::HalfEdgeMesh& unit_box_mesh();

// A convex polytope as SAT and the manifold builder see it, in its core frame.
struct SatPolytope {
  const hull::HalfEdgeMesh* mesh = nullptr;                // topology
  const Eigen::Vector3d* vertices = nullptr;               // positions, indexed like mesh
  const hull::Plane* planes = nullptr;                     // face planes; null: mesh->plane(f)
  const ConvexPolyhedron* poly = nullptr;                  // hulls: the support walks its adjacency
  mutable hull::Index hint = 0;                            // last support vertex (climb start)
  double scale = 0.0;                                      // bounding radius of the core
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  // boxes (poly == nullptr)

  const Eigen::Vector3d& vertex(hull::Index v) const { return vertices[v]; }
  const hull::Plane& plane(hull::Index f) const { return planes ? planes[f] : mesh->plane(f); }
  // A vertex maximising d . x.
  hull::Index support(const Eigen::Vector3d& d) const {
    if (!poly)  // a box: the sign bits of d (ties to +, like BoxCore)
      return static_cast<hull::Index>((d.x() >= 0 ? 1 : 0) | (d.y() >= 0 ? 2 : 0) | (d.z() >= 0 ? 4 : 0));
    hint = polyhedron_support(*poly, d, hint);
    return hint;
  }
};

// Storage for a box's polytope (lives on the caller's stack).
struct BoxPolytopeStorage {
  std::array<Eigen::Vector3d, 8> vertices;
  std::array<hull::Plane, 6> planes;
};

SatPolytope sat_polytope(const Box& box, BoxPolytopeStorage& storage);
// Requires poly.dimension() == 3 for a meaningful SAT.
SatPolytope sat_polytope(const ConvexPolyhedron& poly);

struct SatAxis {
  SatAxisKind kind = SatAxisKind::none;
  double separation = -std::numeric_limits<double>::infinity();
  hull::Index feature_a = hull::kInvalidIndex;  // face of A, or half-edge of A
  hull::Index feature_b = hull::kInvalidIndex;  // face of B, or half-edge of B
  // Unit axis from A toward B, A's frame (face of B: minus its normal).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
};

struct SatSettings {
  // Edge pairs with |e_A x e_B| below this times |e_A||e_B| are skipped.
  double parallel_tolerance = 0.005;
  // Stop as soon as an axis separates by more than this (A's units).
  double early_out = 0.0;
};

struct SatResult {
  SatAxis face_a;          // best face axis of A
  SatAxis face_b;          // best face axis of B
  SatAxis edge;            // best edge axis (kind none when no pair qualified)
  bool separated = false;  // some axis separates by more than early_out
  int edge_pairs = 0;      // edge pairs that passed the Gauss-map test
};

// The full test; b is placed in a's frame by `b_in_a`.
SatResult sat_query(const SatPolytope& a, const SatPolytope& b, const RelativePose& b_in_a,
                    const SatSettings& settings = {});

// Separation along one face axis (of A when face_of_a, else of B), as the
// full test computes it; used to re-validate a cached axis.
SatAxis sat_face_axis(const SatPolytope& a, const SatPolytope& b, const RelativePose& b_in_a, bool face_of_a,
                      hull::Index face);

}  // namespace hedra::collision
