// Helpers shared by the collision tests: hull construction, seeded random
// points and directions, world-frame vertices, support values of posed shapes
// (for optimality checks of witness points and normals), point/segment/
// triangle distances, the exact reference distance between point sets
// (tools/reference, independent of GJK/EPA), and a point's signed distance
// to a posed shape's surface.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <exact_reference.hpp>
#include <hedra/collision/detail/minkowski.hpp>
#include <hedra/collision/detail/support.hpp>
#include <hedra/collision/shapes.hpp>
#include <limits>
#include <memory>
#include <qhull_reference.hpp>
#include <random>
#include <vector>

namespace hedra::collision::testing {

using Vec = Eigen::Vector3d;

inline std::shared_ptr<const ConvexPolyhedron> make_hull(const std::vector<Vec>& points) {
  ConvexPolyhedron::BuildResult built = ConvexPolyhedron::build(points);
  EXPECT_TRUE(built.ok()) << built.message;
  return built.polyhedron;
}

inline Vec random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Vec(g(rng), g(rng), g(rng)).normalized();
}

// n points uniform in the box [-scale, scale].
inline std::vector<Vec> random_points(std::mt19937_64& rng, int n, const Vec& scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec> p;
  for (int i = 0; i < n; ++i) p.push_back(Vec(u(rng), u(rng), u(rng)).cwiseProduct(scale));
  return p;
}

inline std::vector<Vec> posed(const std::vector<Vec>& local, const Pose& pose) {
  std::vector<Vec> out;
  for (const Vec& v : local) out.push_back(pose.apply(v));
  return out;
}

// A polyhedron's vertices in the world frame (it stores them recentred).
inline std::vector<Vec> world_vertices(const ConvexPolyhedron& poly, const Pose& pose) {
  std::vector<Vec> out;
  for (const Vec& v : poly.vertices()) out.push_back(pose.apply(poly.offset() + v));
  return out;
}

// max over the posed shape of n . x.
inline double support_value(const Shape& s, const Pose& pose, const Vec& n) {
  return n.dot(pose.apply(support(s, pose.rotation.transpose() * n)));
}

// Closest point to p on the segment ab.
inline Vec closest_on_segment(const Vec& p, const Vec& a, const Vec& b) {
  const Vec ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 == 0.0) return a;
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return a + t * ab;
}

// Distance from p to triangle abc to p: minimum over the interior critical
// point (if inside) and the three edges (each a clamped 1D projection).
inline double point_triangle_distance(const Vec& p, const Vec& a, const Vec& b, const Vec& c) {
  const Vec n = (b - a).cross(c - a);
  double best = std::min({(closest_on_segment(p, a, b) - p).norm(), (closest_on_segment(p, b, c) - p).norm(),
                          (closest_on_segment(p, c, a) - p).norm()});
  const double nn = n.squaredNorm();
  if (nn > 0.0) {
    const Vec q = p - (n.dot(p - a) / nn) * n;  // projection on the plane
    const bool inside =
        n.dot((b - a).cross(q - a)) >= 0.0 && n.dot((c - b).cross(q - b)) >= 0.0 && n.dot((a - c).cross(q - c)) >= 0.0;
    if (inside) best = std::min(best, (q - p).norm());
  }
  return best;
}

// Distance between the convex hulls of two world point sets (0 when they
// overlap): the exact reference (tools/reference/exact_reference.hpp, the
// origin against qhull's hull of {a_i - b_j}).
inline double reference_distance(const std::vector<Vec>& a, const std::vector<Vec>& b) {
  const reference::ExactResult r = reference::exact_signed_distance(a, b);
  EXPECT_TRUE(r.ok) << r.reason;
  return std::max(0.0, r.distance);
}

// Distance from (x, y) to the segment p-q in the plane.
inline double segment_distance_2d(const Eigen::Vector2d& x, const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
  const Eigen::Vector2d d = q - p;
  const double t = std::clamp((x - p).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p + t * d - x).norm();
}

// Signed distance of a local point to a cone's core (apex (0, 0, h), base
// disc of radius r at z = -h), exact: in the half-plane (radial, z) the core
// is the triangle (0, -h), (r, -h), (0, h); outside, the distance to its base
// and slant edges; inside, the larger of the two facets' signed distances.
inline double cone_distance(const Cone& c, const Vec& local) {
  const Eigen::Vector2d x(std::hypot(local.x(), local.y()), local.z());
  const double h = c.half_length, r = c.radius;
  const Eigen::Vector2d base0(0.0, -h), rim(r, -h), apex(0.0, h);
  const Eigen::Vector2d slant_normal = Eigen::Vector2d(2.0 * h, r).normalized();  // out of the slant side
  const double base = -h - x.y(), slant = slant_normal.dot(x - apex);
  if (base <= 0.0 && slant <= 0.0) return std::max(base, slant);
  return std::min(segment_distance_2d(x, base0, rim), segment_distance_2d(x, rim, apex));
}

// Signed distance of world point x to a posed shape's surface (margins
// included): exact on and outside it (closed forms; a hull's through the
// exact reference outside), <= 0 inside (hulls: the largest plane distance).
inline double surface_distance(const Shape& s, const Pose& pose, const Vec& x) {
  const Vec local = pose.rotation.transpose() * (x - pose.translation);
  if (const Box* b = std::get_if<Box>(&s)) {
    const Vec q = local.cwiseAbs() - b->half_extents;
    return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0) - b->margin;
  }
  if (const Capsule* c = std::get_if<Capsule>(&s)) {
    const Vec p(0.0, 0.0, std::clamp(local.z(), -c->half_length, c->half_length));
    return (local - p).norm() - c->radius - c->margin;
  }
  if (const Sphere* b = std::get_if<Sphere>(&s)) return local.norm() - b->radius - b->margin;
  if (const Cone* c = std::get_if<Cone>(&s)) return cone_distance(*c, local) - c->margin;
  if (const Cylinder* c = std::get_if<Cylinder>(&s)) {
    const double radial = std::hypot(local.x(), local.y()) - c->radius;
    const double axial = std::abs(local.z()) - c->half_length;
    return std::hypot(std::max(radial, 0.0), std::max(axial, 0.0)) + std::min(std::max(radial, axial), 0.0) - c->margin;
  }
  const Polyhedron& p = std::get<Polyhedron>(s);
  const ConvexPolyhedron& h = *p.hull;
  const Vec v = local - h.offset();
  double plane = -INFINITY;
  for (hull::Index f = 0; f < h.mesh().face_count(); ++f) plane = std::max(plane, h.mesh().plane(f).signed_distance(v));
  if (plane <= 0.0) return plane - p.margin;
  return reference_distance(world_vertices(h, pose), {x}) - p.margin;
}

// Exact signed distance of two point sets' hulls (world points), via qhull:
// > 0 the distance, < 0 minus the penetration depth (the distance from the
// origin, inside, to the Minkowski difference's boundary: the smallest
// facet-plane distance).
inline double signed_reference_distance(const std::vector<Vec>& a, const std::vector<Vec>& b) {
  std::vector<Vec> diff;
  for (const Vec& p : a)
    for (const Vec& q : b) diff.push_back(p - q);
  const reference::QhullHull h = reference::qhull_hull(diff, "Qt");
  EXPECT_TRUE(h.ok) << h.messages;
  bool outside = false;
  double best = INFINITY, depth = INFINITY;
  for (const auto& t : h.triangles) {
    const Vec &p0 = diff[t[0]], &p1 = diff[t[1]], &p2 = diff[t[2]];
    Vec n = (p1 - p0).cross(p2 - p0);
    if (n.squaredNorm() == 0.0) continue;
    n.normalize();
    const double plane = n.dot(-p0);  // signed distance of the origin to the facet's plane
    if (plane > 0.0) outside = true;
    depth = std::min(depth, -plane);
    best = std::min(best, point_triangle_distance(Vec::Zero(), p0, p1, p2));
  }
  return outside ? best : -depth;
}

// Segment-segment distance: the minimum of the convex quadratic
// |p0 + s u - q0 - t v|^2 over [0,1]^2 is at the interior stationary point
// if that lies inside, otherwise on the boundary (four point-segment cases).
inline double segment_distance(const Vec& p0, const Vec& p1, const Vec& q0, const Vec& q1) {
  const Vec u = p1 - p0, v = q1 - q0, w = p0 - q0;
  double best = std::min({(closest_on_segment(p0, q0, q1) - p0).norm(), (closest_on_segment(p1, q0, q1) - p1).norm(),
                          (closest_on_segment(q0, p0, p1) - q0).norm(), (closest_on_segment(q1, p0, p1) - q1).norm()});
  const double a = u.dot(u), b = u.dot(v), c = v.dot(v), d = u.dot(w), e = v.dot(w);
  const double den = a * c - b * b;
  if (den > 1e-12 * a * c) {
    const double s = (b * e - c * d) / den, t = (a * e - b * d) / den;
    if (s >= 0 && s <= 1 && t >= 0 && t <= 1) best = std::min(best, (w + s * u - t * v).norm());
  }
  return best;
}

// max over unit n of -(h_A(n) + h_B(-n)) scanned over the great circles
// perpendicular to each of `axes` (a scan of 2000 steps, then 3 zooms): a
// certified lower bound of the signed distance of two posed shapes
// (sd >= -h_D(n) for every n), tight for nearly coaxial cylinders, whose
// h_D has its kinks on those circles.
inline double lower_bound_over_great_circles(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb,
                                             const std::vector<Vec>& axes) {
  double lower = -std::numeric_limits<double>::infinity();
  for (const Vec& k : axes) {
    const Vec e1 = k.unitOrthogonal(), e2 = k.cross(e1);
    double lo = 0.0, hi = 2.0 * M_PI, best_phi = 0.0;
    for (int zoom = 0; zoom < 4; ++zoom) {
      const int steps = 2000;
      for (int j = 0; j <= steps; ++j) {
        const double phi = lo + (hi - lo) * j / steps;
        const Vec n = std::cos(phi) * e1 + std::sin(phi) * e2;
        const double value = -(support_value(a, pa, n) + support_value(b, pb, -n));
        if (value > lower) {
          lower = value;
          best_phi = phi;
        }
      }
      const double width = 2.0 * (hi - lo) / steps;
      lo = best_phi - width;
      hi = best_phi + width;
    }
  }
  return lower;
}

// A needle tetrahedron (length 1..1e3, aspect 1e4..1e10: within h of the
// x axis in its frame) posed at random, and a point `gap` (0.1 h .. 10 h)
// above the interior of its top face (z = 0 in its frame), so the distance
// is `gap` by construction. `slack` covers the rounding of the posed
// vertices (64 eps of the coordinates).
struct NeedleAndPoint {
  std::vector<Vec> needle;  // world vertices
  Vec point;                // world
  double gap = 0.0;
  double length = 0.0;
  double slack = 0.0;
};

inline NeedleAndPoint needle_and_point_above_it(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  NeedleAndPoint c;
  c.length = std::pow(10.0, 3.0 * u(rng));
  const double h = c.length * std::pow(10.0, -4.0 - 6.0 * u(rng));
  c.gap = h * std::pow(10.0, -1.0 + 2.0 * u(rng));
  const double s = 0.2 + 0.6 * u(rng);
  const double length = c.length;
  const std::vector<Vec> local = {
      {-length * s, 0, 0}, {length * (1 - s), 0, 0}, {0, h, 0}, {0.1 * length, 0.5 * h, -h}};
  const double x = length * (-s + u(rng));
  const double y_max = h * (x < 0 ? 1 + x / (length * s) : 1 - x / (length * (1 - s)));
  const Vec above(x, y_max * (0.05 + 0.9 * u(rng)), c.gap);
  // Braced lists: their arguments are drawn in order on every compiler.
  const Eigen::Quaterniond q{g(rng), g(rng), g(rng), g(rng)};
  const Vec t = length * Vec{g(rng), g(rng), g(rng)};
  const Eigen::Matrix3d r = q.normalized().toRotationMatrix();
  for (const Vec& p : local) c.needle.push_back(r * p + t);
  c.point = r * above + t;
  c.slack = 64 * std::numeric_limits<double>::epsilon() * (length + t.cwiseAbs().maxCoeff());
  return c;
}

}  // namespace hedra::collision::testing
