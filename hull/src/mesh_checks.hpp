// The parts of HalfEdgeMesh::validate() a builder needs on a mesh whose
// links it has already checked (quickhull checks its working structure's
// links, cycles and V - E + F = 2 in the walk that compacts it): the vertex
// rings (one fan per vertex) and each face's geometry (unit normal, planar
// within tol, wound along its normal, convex at each corner and turning
// once, neighbouring vertices behind its plane), with validate()'s messages.
// Precondition: every index in range and the links consistent; otherwise
// call validate().
#pragma once

#include <hedra/hull/half_edge_mesh.hpp>

namespace hedra::hull::detail {

ValidationReport validate_rings_and_faces(const HalfEdgeMesh& mesh, double tolerance);

}  // namespace hedra::hull::detail
