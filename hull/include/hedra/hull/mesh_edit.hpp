// Editing operations on a HalfEdgeMesh: split an edge, split a face along a
// diagonal, cut the polyhedron by a plane; and a tiny allocation-free clipper
// of a convex polygon by a plane (for contact clipping).
//
// Every operation either leaves the mesh unchanged (and says so) or leaves it
// with every invariant of half_edge_mesh.hpp intact, so validate() passes
// after each call on a valid input. split_edge / split_face are local,
// in-place, O(face degree), append new elements and never invalidate indices.
// cut_by_plane classifies vertices with the mesh's tolerance (a plane within
// it of a vertex goes through the vertex: no slivers), rebuilds the kept part
// into fresh arrays and caps the opening (a flat mesh is cut across); when
// the border is not one simple loop it changes nothing (topology_failure).
// How the kept part is built: docs/design.md (hull).
#pragma once

#include <cstddef>
#include <hedra/hull/half_edge_mesh.hpp>
#include <vector>

namespace hedra::hull {

// ---- split_edge ------------------------------------------------------------
// Inserts a new vertex at `point` on the edge of half-edge `e`: e (a->b) and
// its twin (b->a) become a->m, m->b and b->m, m->a; both faces gain the vertex
// m and keep their planes. Returns m, or kInvalidIndex (mesh unchanged) when e
// is out of range or the point is not finite.
//
// The point is used as given. When it lies on the segment (within
// tolerance()) every invariant holds and m has degree two. When it does not,
// the structure stays a valid closed 2-manifold but the geometry does not:
// validate() reports m as off the two face planes, or a face as non-convex
// at m. Project the point onto the segment first if that is not intended.
Index split_edge(HalfEdgeMesh& mesh, Index e, const Eigen::Vector3d& point);

// ---- split_face ------------------------------------------------------------
// Splits face f along the diagonal v_a - v_b. Face f keeps the part that
// starts at v_a (v_a, ..., v_b counter-clockwise) and the returned new face
// the part v_b, ..., v_a; both get f's plane (they lie in it). Returns the new
// face's index, or kInvalidIndex (mesh unchanged) when f is out of range,
// either vertex is not on f, the two are equal or adjacent on f, or one of the
// two parts would have no area (all its vertices within tolerance() of the
// diagonal's line, e.g. v_a and v_b on one side of f after split_edge).
Index split_face(HalfEdgeMesh& mesh, Index f, Index v_a, Index v_b);

// ---- cut_by_plane ----------------------------------------------------------
enum class CutStatus {
  unchanged,         // no vertex more than tolerance in front: mesh untouched
  cut,               // the front part was removed and the opening capped
  emptied,           // no vertex more than tolerance behind: nothing with
                     // thickness remains behind the plane; the mesh is cleared
  invalid_plane,     // zero or non-finite normal, or non-finite offset: untouched
  invalid_mesh,      // empty mesh, non-finite positions (or so large that edge
                     // vectors overflow), or out-of-range or inconsistent links
                     // (twins, next/prev, faces, origins): untouched
  topology_failure,  // the classification gave no single border loop (see the
                     // note at the top): untouched
};

const char* to_string(CutStatus status);

struct CutResult {
  CutStatus status = CutStatus::unchanged;
  // The cap face (its plane is the normalised cutting plane); kInvalidIndex
  // unless status == cut on a solid (a flat mesh is cut across, not capped).
  Index cap_face = kInvalidIndex;
  std::size_t removed_vertices = 0;  // input vertices not in the result
  std::size_t added_vertices = 0;    // new vertices where edges crossed the plane
  // For each face of the result, the input face it is a part of
  // (kInvalidIndex for the cap). Filled only when status == cut.
  std::vector<Index> face_source;
};

// Keeps the part of `mesh` behind `plane` (signed distance <= 0), see the
// note at the top. The plane's normal need not be unit length; it is
// normalised first. Works on solids, flat two-sided polygons, segments and
// points (a segment or point is clipped directly; a segment that would
// shrink to a point within tolerance counts as emptied). Vertices within
// mesh.tolerance() of the plane count as on it; when the mesh has no positive
// tolerance one is derived from its extent as from_polygons() does.
CutResult cut_by_plane(HalfEdgeMesh& mesh, const Plane& plane);

// ---- clip_polygon ----------------------------------------------------------
enum class ClipStatus {
  ok,                 // out[0, count) holds the clipped polygon (may be empty)
  capacity_exceeded,  // `capacity` was too small: count is what fit, truncated
  invalid_input,      // non-finite point or plane, zero normal, or a crossing
                      // that overflows: count = 0
};

struct ClipResult {
  ClipStatus status = ClipStatus::ok;
  std::size_t count = 0;
};

// Clips the convex polygon points[0, count) (in order, either winding) by
// `plane`, keeping the part behind it, Sutherland-Hodgman style, into the
// caller's buffer out[0, capacity) without allocating. Points within
// `tolerance` of the plane count as on it: they are kept and produce no
// intersection point, so no near-duplicate points appear. tolerance <= 0
// derives one from the extent of the points and the plane offset. The output
// keeps the input's order and winding; a convex n-gon yields at most n + 1
// points. count == 1 (a point) and count == 2 (a segment) are clipped as such.
// `out` must not overlap `points`. The plane normal need not be unit length.
ClipResult clip_polygon(const Eigen::Vector3d* points, std::size_t count, const Plane& plane, Eigen::Vector3d* out,
                        std::size_t capacity, double tolerance = 0.0);

}  // namespace hedra::hull
