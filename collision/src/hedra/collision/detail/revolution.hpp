// Penetration of two cores of revolution with parallel axes, exactly, by
// reduction to the meridian plane.
//
// Where the depth is the same over a circle of directions (a ball on a
// cylinder's axis, coaxial cylinders and cones) EPA's lower bound rises only
// as the square of its polytope's resolution. With parallel axes D = A - B
// is itself a solid of revolution; its meridian section is the Minkowski sum
// of the cores' sections (polygons of at most 4 vertices, so at most 16
// sums), the 3D depth is the 2D depth of the origin in that section, and
// the witnesses are the section points placed back in the meridian plane.
// Axes parallel only within theta: the answer is within theta R_B
// (reported in error_bound); the reduction is taken when that is below half
// the EPA tolerance, or at any tilt with RevolutionTilt::any (a bracket).
// Derivations: docs/design.md, "Parallel cores of revolution".
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <hedra/collision/detail/epa.hpp>
#include <hedra/collision/detail/minkowski.hpp>
#include <limits>

namespace hedra::collision {

namespace revolution_detail {

// The meridian section of a core of revolution in (radial, axial)
// coordinates of its own frame, both sides of the axis; `free_axis` for a
// point (symmetric about any axis), `curved` for a cylinder or a cone.
struct Section {
  int count = 0;  // 0: not a core of revolution
  std::array<Eigen::Vector2d, 4> p;
  bool free_axis = false;
  bool curved = false;
  double radius = 0.0;  // bounding radius of the core
};

template <class Core>
Section section_of(const Core&) {
  return {};
}
inline Section section_of(const PointCore&) {
  Section s;
  s.count = 1;
  s.p[0] = {0.0, 0.0};
  s.free_axis = true;
  return s;
}
inline Section section_of(const SegmentCore& c) {
  Section s;
  s.count = 2;
  s.p[0] = {0.0, -c.half_length};
  s.p[1] = {0.0, c.half_length};
  s.radius = c.half_length;
  return s;
}
inline Section section_of(const CylinderCore& c) {
  Section s;
  s.count = 4;
  s.p = {Eigen::Vector2d(c.radius, -c.half_length), Eigen::Vector2d(-c.radius, -c.half_length),
         Eigen::Vector2d(c.radius, c.half_length), Eigen::Vector2d(-c.radius, c.half_length)};
  s.curved = true;
  s.radius = c.bounding_radius();
  return s;
}
inline Section section_of(const ConeCore& c) {
  Section s;
  s.count = 3;
  s.p[0] = {c.radius, -c.half_length};
  s.p[1] = {-c.radius, -c.half_length};
  s.p[2] = {0.0, c.half_length};
  s.curved = true;
  s.radius = c.bounding_radius();
  return s;
}

inline double cross2(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

}  // namespace revolution_detail

// The exact penetration of A and B (cores, B placed by `relative` in A's
// frame) when both are cores of revolution with parallel axes, at least one
// curved, and the origin is inside D's section; false otherwise (run EPA).
// Same conventions as epa_penetration: point_a - point_b = depth * normal,
// normal from A toward B.
// Which tilt between the two axes revolution_penetration accepts.
enum class RevolutionTilt {
  within_tolerance,  // theta R_B within half the EPA tolerance: the exact answer
  any,               // any finite tilt, theta R_B in error_bound: a bracket
};

template <class CA, class CB>
bool revolution_penetration(const CA& core_a, const CB& core_b, const RelativePose& relative, double scale,
                            const Eigen::Vector3d& preferred, const EpaSettings& settings, EpaResult& out,
                            RevolutionTilt accepted = RevolutionTilt::within_tolerance) {
  using revolution_detail::Section;
  const Section sa = revolution_detail::section_of(core_a);
  const Section sb = revolution_detail::section_of(core_b);
  if (sa.count == 0 || sb.count == 0 || !(sa.curved || sb.curved)) return false;
  const double size = std::isfinite(scale) && scale > 0.0 ? scale : 0.0;
  const Eigen::Vector3d kb = relative.rotation.col(2);
  const Eigen::Vector3d k = sa.free_axis ? kb : Eigen::Vector3d::UnitZ();
  // B's axis against k: the angle, its direction sign, the bound it costs.
  const double sign = sb.free_axis || k.dot(kb) >= 0.0 ? 1.0 : -1.0;
  const double tilt = sb.free_axis ? 0.0 : std::atan2(k.cross(kb).norm(), std::abs(k.dot(kb)));
  const double tilt_bound = tilt * sb.radius;
  const double tolerance = settings.absolute_tolerance * size;
  if (!(tilt_bound <= 0.5 * tolerance) && !(accepted == RevolutionTilt::any && std::isfinite(tilt_bound))) return false;

  // The origin in D's section: D's axis passes through -t (A's axis through
  // the origin, -B's through -t), so the origin sits at t from it.
  const Eigen::Vector3d& t = relative.translation;
  const double z0 = t.dot(k);
  const Eigen::Vector3d perp = t - z0 * k;
  const double rho0 = perp.norm();
  // The meridian half-plane through the origin. A radial offset at the
  // rounding level of t carries no direction (its normalisation would not
  // even be perpendicular to k): the origin is then on the axis, where every
  // meridian plane is equivalent; the one toward `preferred` is taken when
  // it has a radial part.
  const double noise = 16.0 * std::numeric_limits<double>::epsilon() * (t.norm() + size);
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  if (rho0 > noise) e = perp / rho0;
  if (!(rho0 > noise)) e = preferred - preferred.dot(k) * k;
  e -= e.dot(k) * k;
  if (!(e.norm() > 1e-3 * (rho0 > noise ? 1.0 : preferred.norm())) || !e.allFinite()) e = k.unitOrthogonal();
  e.stableNormalize();
  const Eigen::Vector2d q(rho0 > noise ? rho0 : 0.0, z0);

  // D's section: the convex hull of all sums (Andrew's monotone chain over
  // at most 16 points, no allocation).
  struct Sum {
    Eigen::Vector2d p;
    int ia, ib;
  };
  std::array<Sum, 16> sums;
  int n = 0;
  for (int i = 0; i < sa.count; ++i)
    for (int j = 0; j < sb.count; ++j) sums[n++] = {sa.p[i] + Eigen::Vector2d(sb.p[j].x(), -sign * sb.p[j].y()), i, j};
  std::sort(sums.begin(), sums.begin() + n,
            [](const Sum& x, const Sum& y) { return x.p.x() < y.p.x() || (x.p.x() == y.p.x() && x.p.y() < y.p.y()); });
  std::array<Sum, 33> hull;
  int h = 0;
  for (int i = 0; i < n; ++i) {  // lower chain
    while (h >= 2 && revolution_detail::cross2(hull[h - 2].p, hull[h - 1].p, sums[i].p) <= 0.0) --h;
    hull[h++] = sums[i];
  }
  for (int i = n - 2, lower = h + 1; i >= 0; --i) {  // upper chain
    while (h >= lower && revolution_detail::cross2(hull[h - 2].p, hull[h - 1].p, sums[i].p) <= 0.0) --h;
    hull[h++] = sums[i];
  }
  --h;  // the first point closes the chain
  if (h < 3) return false;

  // The nearest edge plane (counter-clockwise polygon: outward normal of
  // edge (p, p') is (dy, -dx) / |d|).
  int best = -1;
  double depth = std::numeric_limits<double>::infinity();
  Eigen::Vector2d normal2 = Eigen::Vector2d::Zero();
  for (int i = 0; i < h; ++i) {
    const Eigen::Vector2d d = hull[i + 1].p - hull[i].p;
    const double len = d.norm();
    if (!(len > 0.0)) continue;
    const Eigen::Vector2d nn(d.y() / len, -d.x() / len);
    const double offset = nn.dot(hull[i].p - q);
    if (offset < depth) {
      depth = offset;
      best = i;
      normal2 = nn;
    }
  }
  // Only an origin strictly inside the section (GJK said the cores overlap;
  // at the boundary EPA's handling of touching applies).
  if (best < 0 || !(depth > 0.0) || !std::isfinite(depth)) return false;
  const Sum& s0 = hull[best];
  const Sum& s1 = hull[best + 1];
  const Eigen::Vector2d d = s1.p - s0.p;
  const double tau = std::clamp((q - s0.p).dot(d) / d.squaredNorm(), 0.0, 1.0);

  // Back to 3D: a section point (x, y) of A is x e + y k; one of -B at
  // (x, y) is -t + x e + y k, so B's point is t - x e - y k.
  const auto point_a = [&](int i) { return Eigen::Vector3d(sa.p[i].x() * e + sa.p[i].y() * k); };
  const auto point_b = [&](int j) { return Eigen::Vector3d(t - sb.p[j].x() * e + sign * sb.p[j].y() * k); };
  EpaResult r;
  r.status = EpaStatus::ok;
  r.iterations = 0;
  r.dimension = 3;
  r.depth = depth;
  r.normal = normal2.x() * e + normal2.y() * k;
  const Eigen::Vector3d pa = (1.0 - tau) * point_a(s0.ia) + tau * point_a(s1.ia);
  const Eigen::Vector3d pb = (1.0 - tau) * point_b(s0.ib) + tau * point_b(s1.ib);
  const Eigen::Vector3d residual = (pa - pb) - depth * r.normal;
  r.point_a = pa - 0.5 * residual;
  r.point_b = pb + 0.5 * residual;
  // Rounding of the section sums and of the frame, plus the tilt.
  r.error_bound = tilt_bound + 64.0 * std::numeric_limits<double>::epsilon() * (size + t.norm());
  if (!(r.normal.allFinite() && r.point_a.allFinite() && r.point_b.allFinite())) return false;
  out = r;
  return true;
}

}  // namespace hedra::collision
