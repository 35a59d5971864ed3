// Mass properties of a convex HalfEdgeMesh of uniform density: volume,
// surface area, centroid and the inertia tensor about the centroid.
//
// Method (divergence theorem over triangle fans, in the spirit of Mirtich
// 1996 and Eberly's "Polyhedral Mass Properties"): every face is fanned into
// triangles (p0, p_i, p_i+1) and each triangle, with a reference point r, spans
// a tetrahedron whose signed volume, first and second moments are summed; on a
// closed, consistently wound surface the signed sum is the solid. r is the
// average of the vertices (inside a convex mesh), so all arithmetic is done
// on coordinates relative to the mesh and an offset of 1e6 from the origin
// costs no accuracy. The derivation of the per-tetrahedron formulas:
// docs/design.md (hull).
//
// Degenerate meshes: a flat polygon (two back-to-back faces, or any mesh
// whose signed volume is within rounding of zero) has zero volume and
// inertia; its centroid is the area centroid of the polygon and its surface
// area counts both sides. A segment's centroid is its midpoint, a point's the
// point; both have zero area. No NaN is ever returned.
#pragma once

#include <Eigen/Core>
#include <hedra/hull/half_edge_mesh.hpp>

namespace hedra::hull {

enum class MassStatus {
  ok,             // a solid: every field is meaningful
  flat,           // zero volume (polygon, segment, point): mass and inertia
                  // are zero, centroid and surface area are still meaningful
  invalid_input,  // empty mesh, non-finite position, coordinates so large
                  // that the moments overflow, or a density that is negative
                  // or not finite: every field is zero
};

const char* to_string(MassStatus status);

struct MassProperties {
  MassStatus status = MassStatus::invalid_input;
  double volume = 0.0;
  double mass = 0.0;  // density * volume
  double surface_area = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // of the solid (area centroid when flat)
  // About the centroid, axes of the mesh's frame: I = density * integral of
  // (|x|^2 Id - x x^T) over the solid, x measured from the centroid.
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
};

MassProperties mass_properties(const HalfEdgeMesh& mesh, double density = 1.0);

double volume(const HalfEdgeMesh& mesh);
double surface_area(const HalfEdgeMesh& mesh);
Eigen::Vector3d centroid(const HalfEdgeMesh& mesh);
Eigen::Matrix3d inertia_tensor(const HalfEdgeMesh& mesh, double density = 1.0);

}  // namespace hedra::hull
