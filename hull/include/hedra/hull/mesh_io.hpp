// Reading point sets from .xyz, .obj and .off files, and writing a hull as a
// Wavefront .obj file.
//
// Formats read (only vertex positions; everything else is skipped):
//   .xyz  three numbers per line; blank lines and '#' comments allowed.
//   .obj  `v x y z [w]` lines (w, or the common `v x y z r g b` colour
//         extension, is read and ignored); every other line is ignored.
//   .off  a header line `OFF` (the counts may follow on the same line), a
//         counts line `vertices faces edges`, then that many vertex lines of
//         three numbers; faces and edges are not read. '#' comments allowed.
// In every format a '#' starts a comment that runs to the end of the line,
// lines may end in "\r\n", and numbers are parsed with std::from_chars, so
// the result never depends on the process locale.
//
// Errors are values, never exceptions or exits: a ReadPointsResult either
// holds at least one point, every coordinate finite, or an IoError whose
// message() names the file and the 1-based line ("rock.obj:17: expected 3
// numbers after 'v', found 2"). NaN, infinities and numbers too large for a
// double (1e999) are rejected; numbers too small for a double (1e-400) round
// to zero, as any decimal-to-binary conversion would.
//
// write_obj writes `v` lines at full precision (17 significant digits, so
// reading them back gives the same doubles) and one `f` line per face with
// 1-based indices, counter-clockwise seen from outside as in the mesh; with
// `triangulate` each convex face is written as a fan of triangles.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <hedra/hull/half_edge_mesh.hpp>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hedra::hull {

enum class PointFormat { xyz, obj, off };

const char* to_string(PointFormat format);

// The format named by a path's extension (case-insensitive: .xyz, .obj,
// .off), or nothing for any other extension.
std::optional<PointFormat> format_from_path(std::string_view path);

// Why reading failed.
struct IoError {
  std::string file;      // the path (or stream name) as the caller gave it
  std::size_t line = 0;  // 1-based line of the problem; 0 when it concerns the whole file
  std::string what;      // the problem, without the location

  // "file:line: what", or "file: what" when line is 0.
  std::string message() const;
};

struct ReadPointsResult {
  std::vector<Eigen::Vector3d> points;  // empty whenever error is set
  std::optional<IoError> error;

  bool ok() const { return !error.has_value(); }
};

// Reads the points of the file at `path`, choosing the format by extension.
ReadPointsResult read_points(const std::string& path);

// Reads points in `format` from `in`; `name` stands for the file in messages.
ReadPointsResult read_points(std::istream& in, PointFormat format, std::string_view name = "<stream>");

// Writes `mesh` as OBJ to `out`: a comment line, the vertices, then the faces
// (polygons, or fan triangles when `triangulate`). Point and segment hulls
// have no faces and give `v` lines only. Check out's state for write errors.
void write_obj(const HalfEdgeMesh& mesh, std::ostream& out, bool triangulate = false);

}  // namespace hedra::hull
