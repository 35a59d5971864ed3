// Mass properties by the divergence theorem over triangle fans: each fan
// triangle (a, b, c) spans with the reference point r (the vertex average)
// a signed tetrahedron of volume v = a . (b x c) / 6, first moment v s / 4
// (s = a + b + c) and second moment v / 20 (a a^T + b b^T + c c^T + s s^T);
// the sums over a closed surface are the solid's. Working relative to r keeps
// an offset of 1e6 from costing accuracy. Surface area is half the norm of
// each face's Newell sum. The derivation: docs/design.md (hull).
#include <algorithm>
#include <cmath>
#include <hedra/hull/mass.hpp>
#include <limits>

namespace hedra::hull {

const char* to_string(MassStatus status) {
  switch (status) {
    case MassStatus::ok:
      return "ok";
    case MassStatus::flat:
      return "flat";
    case MassStatus::invalid_input:
      return "invalid_input";
  }
  return "unknown";
}

namespace {

bool structure_ok(const HalfEdgeMesh& mesh) {
  const std::size_t V = mesh.vertices.size(), H = mesh.edges.size();
  if (V == 0) return false;
  for (const auto& v : mesh.vertices)
    if (!v.position.allFinite()) return false;
  for (const auto& h : mesh.edges)
    if (h.origin >= V || h.next >= H) return false;
  for (const auto& f : mesh.faces)
    if (f.edge >= H) return false;
  return true;
}

// Products of coordinates near the overflow limit (|x| ~ 1e100 and up) can
// overflow; such results are reported as invalid rather than as inf or NaN.
MassProperties finite_or_invalid(const MassProperties& m) {
  if (std::isfinite(m.volume) && std::isfinite(m.mass) && std::isfinite(m.surface_area) && m.centroid.allFinite() &&
      m.inertia.allFinite())
    return m;
  return MassProperties{};
}

}  // namespace

MassProperties mass_properties(const HalfEdgeMesh& mesh, double density) {
  MassProperties m;
  if (!std::isfinite(density) || density < 0 || !structure_ok(mesh)) return m;

  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (const auto& v : mesh.vertices) r += v.position;
  r /= static_cast<double>(mesh.vertices.size());

  const std::size_t H = mesh.edges.size();
  double vol = 0, vol_bound = 0, area = 0, triangle_area = 0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Vector3d area_first = Eigen::Vector3d::Zero();  // sum of triangle area * centroid (relative to r)
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (Index f = 0; f < mesh.faces.size(); ++f) {
    const Index start = mesh.faces[f].edge;
    const Eigen::Vector3d a = mesh.position(mesh.edges[start].origin) - r;
    Eigen::Vector3d newell = Eigen::Vector3d::Zero();
    // Fan (a, b, c) over the face; the walk is capped by the half-edge count.
    Index e = mesh.edges[start].next;
    for (std::size_t steps = 0; steps <= H; ++steps) {
      const Index e_next = mesh.edges[e].next;
      if (e_next == start) break;
      const Eigen::Vector3d b = mesh.position(mesh.edges[e].origin) - r;
      const Eigen::Vector3d c = mesh.position(mesh.edges[e_next].origin) - r;
      const Eigen::Vector3d s = a + b + c;
      const Eigen::Vector3d n = (b - a).cross(c - a);
      const double v = a.dot(b.cross(c)) / 6.0;
      vol += v;
      vol_bound += a.norm() * b.cross(c).norm() / 6.0;
      first += v * s / 4.0;
      second += (v / 20.0) * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
      newell += n;
      const double tri_area = 0.5 * n.norm();
      triangle_area += tri_area;
      area_first += tri_area * s / 3.0;
      e = e_next;
    }
    area += 0.5 * newell.norm();
  }
  m.surface_area = area;

  // Flat: the volume is indistinguishable from rounding. Each term's error
  // is a few ulps of |a| |b x c| / 6, so a signed sum within 64 eps of the
  // sum of those bounds is noise (a two-sided polygon cancels to that
  // level); a genuine solid, however thin, is far above it.
  if (mesh.faces.empty() || !(std::abs(vol) > 64.0 * std::numeric_limits<double>::epsilon() * vol_bound)) {
    m.status = MassStatus::flat;
    // Triangle fan sums double-count a two-sided polygon, which cancels here.
    // Area centroid of the surface: for a two-sided polygon both sides give
    // the same weights, so it is the polygon's own area centroid. Without
    // area (segment, point) it is the vertex average.
    m.centroid = triangle_area > 0 ? Eigen::Vector3d(r + area_first / triangle_area) : r;
    return finite_or_invalid(m);
  }
  const Eigen::Vector3d g = first / vol;
  const Eigen::Matrix3d c = second - vol * g * g.transpose();
  m.status = MassStatus::ok;
  m.volume = vol;
  m.mass = density * vol;
  m.centroid = r + g;
  m.inertia = density * (c.trace() * Eigen::Matrix3d::Identity() - c);
  return finite_or_invalid(m);
}

double volume(const HalfEdgeMesh& mesh) { return mass_properties(mesh).volume; }
double surface_area(const HalfEdgeMesh& mesh) { return mass_properties(mesh).surface_area; }
Eigen::Vector3d centroid(const HalfEdgeMesh& mesh) { return mass_properties(mesh).centroid; }
Eigen::Matrix3d inertia_tensor(const HalfEdgeMesh& mesh, double density) {
  return mass_properties(mesh, density).inertia;
}

}  // namespace hedra::hull
