// World-frame polygon meshes of hedra::collision shapes, for drawing.
//
// Every shape is drawn as the convex hull (hull/'s quickhull, coplanar faces
// merged into polygons) of points on its surface, in its local frame, then
// placed by the pose:
//   box          its 8 corners (exact: 6 quads);
//   cylinder     two rims of `segments` points (exact but for the rims: the
//                side is `segments` quads, the caps two polygons);
//   cone         the apex and a rim of `segments` points;
//   sphere       a latitude-longitude grid of `segments` x `segments / 2`;
//   capsule      its segment's two ends, each with that grid (the side
//                becomes quads, the ends hemispheres);
//   hull         the polyhedron's own half-edge mesh (its merged polygon
//                faces, exact; no re-hulling).
// Margins are drawn as the rounded outline: the Minkowski sum of the core's
// points with a latitude-longitude grid of radius `margin` (`margin_segments`
// around), hulled; its flat faces are exact where the grid has the face's
// normal (the six axis directions, so a rounded box's faces are), and every
// drawn point lies on the true rounded surface, so the drawing is inscribed
// in it. The core (the shape without its margin) comes back separately for
// drawing as edges inside.
//
// The hull is taken in the local frame, so the pose's translation (however
// large) does not coarsen the tessellation; vertices are posed at the end.
#pragma once

#include <hedra/collision/detail/minkowski.hpp>
#include <hedra/collision/shapes.hpp>
#include <hedra/hull/half_edge_mesh.hpp>
#include <string>

#include "cli/view/view_model.hpp"

namespace hedra::tool::view {

struct TessellationOptions {
  int segments = 32;         // points around a circle of a curved surface (>= 3)
  int margin_segments = 16;  // around the ball added for a margin (>= 4)
};

struct TessellatedShape {
  PolygonMesh mesh;   // the whole shape, margin included, world frame
  PolygonMesh core;   // the shape without its margin (empty when margin == 0)
  std::string error;  // why it could not be drawn (invalid shape, hull failure); empty when ok
  bool ok() const { return error.empty(); }
};

// "sphere", "box", "capsule", "cylinder", "cone" or "hull".
const char* shape_kind(const collision::Shape& shape);

TessellatedShape tessellate(const collision::Shape& shape, const collision::Pose& pose,
                            const TessellationOptions& options = {});

// A body of the view: name, kind, margin and tessellate()'s meshes.
// Returns false with `error` set ("body NAME: reason") when it cannot be drawn.
bool make_view_body(const std::string& name, const collision::Shape& shape, const collision::Pose& pose, ViewBody& body,
                    std::string& error, const TessellationOptions& options = {});

// The polygons and edges (each undirected edge once) of a half-edge mesh,
// each vertex mapped by `transform`; a segment hull (two vertices, no edges)
// gets its segment as an edge.
template <class Transform>
PolygonMesh polygon_mesh(const hull::HalfEdgeMesh& mesh, Transform transform) {
  PolygonMesh out;
  out.vertices.reserve(mesh.vertex_count());
  for (const hull::Vertex& vertex : mesh.vertices) out.vertices.push_back(transform(vertex.position));
  out.faces = mesh.polygons();
  for (hull::Index e = 0; e < mesh.half_edge_count(); ++e) {
    if (e < mesh.twin(e)) out.edges.push_back({mesh.origin(e), mesh.destination(e)});
  }
  if (out.edges.empty() && mesh.vertex_count() == 2) out.edges.push_back({0, 1});
  return out;
}

}  // namespace hedra::tool::view
