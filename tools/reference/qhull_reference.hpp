// The exact, independent reference for hedra's hull builder: qhull's
// reentrant C library (libqhull_r, Barber, Dobkin, Huhdanpaa 1996), called
// through its documented C API. Tests and benchmarks compare hedra against
// it; the hedra libraries never include or link it (the arrows point down).
//
// Error handling: qhull reports errors by longjmp back to a setjmp in
// qh_new_qhull, which then returns a non-zero exit code; its messages go to
// an error FILE, here an in-memory stream whose text is returned. Every call
// frees qhull's memory (qh_freeqhull + qh_memfreeshort) whatever happened, and
// reports the bytes qhull could not free (expected 0). Non-finite input is
// rejected before qhull sees it (qhull has crashed on NaN, scipy#5471).
//
// qhull fails outright (QH6154, QH6214, ...) on inputs that are not full
// dimensional: fewer than 4 points, all equal, collinear or coplanar. The
// reference then says so (ok == false) rather than guessing.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace hedra::reference {

struct QhullHull {
  bool ok = false;       // qhull built a hull; all outputs below are valid
  int exit_code = 0;     // qhull's exit code (0 on success), -1 if rejected before qhull ran
  std::string messages;  // everything qhull wrote to its error stream (errors and warnings)
  std::string options;   // the qhull options used, e.g. "Qt"

  std::vector<int> vertices;                  // input indices of the hull vertices, sorted ascending
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise seen from outside (input indices)
  // The plane of each triangle's qhull facet: (n, offset) with n the outward
  // unit normal and n . x + offset = 0 on the facet (qhull's facet->normal
  // and facet->offset; the triangles of one merged facet share its plane).
  std::vector<Eigen::Vector4d> triangle_planes;
  // qhull's facets as polygons (input indices, counter-clockwise seen from
  // outside): triangles under "Qt", merged convex polygons without it.
  std::vector<std::vector<int>> facets;
  std::size_t facet_count = 0;  // = facets.size()
  double volume = 0.0;          // qh_getarea: qh->totvol
  double area = 0.0;            // qh_getarea: qh->totarea

  // Signs that the input is not in general position at qhull's precision:
  // input points qhull kept as coplanar with a facet (only recorded with
  // option "Qc"; 0 otherwise) and triangles that came from triangulating a
  // merged, non-simplicial facet (only with "Qt").
  std::size_t coplanar_points = 0;
  std::size_t tricoplanar_facets = 0;
  std::size_t merged_facets = 0;  // facets that are not simplicial (without "Qt")
  double max_outside = 0.0;       // qh->max_outside: largest distance of a point above its facet

  int leaked_bytes = 0;  // long memory qhull failed to free (expected 0)

  // Whether qhull saw nothing degenerate: no coplanar point, no merged facet.
  bool general_position() const { return ok && coplanar_points == 0 && tricoplanar_facets == 0 && merged_facets == 0; }
};

// Builds the convex hull of `points` with qhull and the given options (qhull's
// option string without the leading "qhull", e.g. "Qt", "Qt Qc", "" for the
// default merged facets).
QhullHull qhull_hull(const std::vector<Eigen::Vector3d>& points, const char* options = "Qt");

// Benchmark entry: builds the hull and frees it, nothing else (no output
// extraction, no area/volume). The input is copied into a reused per-thread
// buffer first (qhull may transform its input in place for some options), a
// memcpy that is comparable to hedra's own recentred copy. Returns the number
// of hull vertices, or -1 when qhull failed.
long qhull_build_only(const Eigen::Vector3d* points, std::size_t count, const char* options);

}  // namespace hedra::reference
