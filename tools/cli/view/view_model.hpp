// What `hedra view` draws: a plain description of a scene (bodies as
// world-frame polygon meshes, queries with their results) or of one convex
// hull (input points, hull faces, half-edges), independent of how it was
// obtained. The scene parser fills it from a scene file (see
// build_scene_view_model in view_command.cpp); `hedra view --hull` fills it
// from a point file; render_view_html (view_html.hpp) turns it into one
// self-contained HTML page.
//
// Frames and units: everything is in the world frame of the scene (the input
// points' frame for a hull), in the scene's units. Optional fields are absent
// when the query type does not produce them (an `intersect` query has no
// distance, a separated `penetration` has no contacts...); absent values are
// written as JSON null and the page says "n/a".
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hedra::tool::view {

// A convex polygon mesh: faces list vertex indices counter-clockwise seen
// from outside; `edges` are the segments to draw (each polygon edge once,
// plus the segment of a degenerate, faceless mesh).
struct PolygonMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::vector<std::uint32_t>> faces;
  std::vector<std::array<std::uint32_t, 2>> edges;
};

struct ViewBody {
  std::string name;
  std::string shape;  // "sphere", "box", "capsule", "cylinder", "cone", "hull"
  double margin = 0.0;
  // The whole shape (margin included) in the world frame. Exact for a box,
  // cylinder, cone or hull without margin (the hull's merged polygon faces);
  // curved and rounded surfaces are an inscribed tessellation (tessellate.hpp).
  PolygonMesh mesh;
  // With a margin: the core (the shape before rounding), drawn as edges
  // inside the rounded outline. Empty otherwise.
  PolygonMesh core;
};

struct ViewContact {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double depth = 0.0;  // > 0 penetration, < 0 speculative (inside the margin)
};

// A moving body of a continuous query, drawn in three poses: where it
// starts, where it ends and where it is at the query's fraction (the time of
// impact; the end pose again when nothing is hit).
struct ViewSweep {
  std::string body;  // body name
  PolygonMesh start, end, at_fraction;
};

// A raycast query's ray: from origin to origin + max_fraction direction,
// and the hit point when there is one.
struct ViewRay {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d end = Eigen::Vector3d::Zero();
  std::optional<Eigen::Vector3d> hit_point;
};

struct ViewQuery {
  std::string a, b;    // body names (raycast: both the body)
  std::string type;    // "intersect", "distance", "penetration", "contact", "raycast", "cast", "toi"
  std::string status;  // "ok" or the word saying what went wrong
  std::optional<bool> intersecting;
  std::optional<double> distance;  // signed for penetration and contact
  std::optional<Eigen::Vector3d> point_a, point_b;
  std::optional<Eigen::Vector3d> normal;  // unit, from A toward B
  std::vector<ViewContact> contacts;
  // Continuous queries (raycast, cast, toi).
  std::optional<bool> hit;
  std::optional<double> fraction;
  std::optional<bool> initially_overlapping;
  std::vector<ViewSweep> sweeps;  // cast, toi: each body that moves
  std::optional<ViewRay> ray;     // raycast
};

// One half-edge of the hull (indices into ViewHull's arrays).
struct ViewHalfEdge {
  std::uint32_t origin = 0;
  std::uint32_t twin = 0;
  std::uint32_t next = 0;
  std::uint32_t face = 0;  // the face on its left
};

struct ViewHull {
  std::string input;                              // the input file, as given
  std::vector<Eigen::Vector3d> input_points;      // possibly a subsample, see input_count
  std::size_t input_count = 0;                    // points in the input file
  std::vector<Eigen::Vector3d> vertices;          // hull vertices
  std::vector<std::vector<std::uint32_t>> faces;  // merged convex polygons, CCW from outside
  std::vector<ViewHalfEdge> half_edges;
  // Per face its half-edges (indices into half_edges), in order around it.
  std::vector<std::vector<std::uint32_t>> face_half_edges;
  std::size_t edge_count = 0;  // undirected edges (half_edges.size() / 2)
  int dimension = 3;           // 0 point, 1 segment, 2 flat polygon, 3 solid
  double volume = 0.0;
  double area = 0.0;
  double max_outside_distance = 0.0;
};

struct ViewModel {
  std::string title;
  std::string description;  // a scene's "description", shown under the title
  std::vector<ViewBody> bodies;
  std::vector<ViewQuery> queries;
  std::optional<ViewHull> hull;
  std::vector<std::string> notes;  // shown in the side panel (e.g. "showing 100000 of 2000000 points")
};

}  // namespace hedra::tool::view
