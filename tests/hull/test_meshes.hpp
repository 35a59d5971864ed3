// Hand-built convex meshes for the hull tests, made with from_polygons only
// (no hull builder), with known counts and closed-form mass properties:
// axis-aligned boxes (vertex and face numbering documented below), general
// tetrahedra, regular prisms and bipyramids, flat two-sided polygons,
// segments and points. Random convex solids are random prisms and bipyramids
// over random convex polygons; every builder asserts (via gtest) that
// from_polygons accepted the polygons and that the result validates.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <hedra/hull/half_edge_mesh.hpp>
#include <random>
#include <string>
#include <vector>

namespace hedra::hull::test {

inline HalfEdgeMesh mesh_from(const std::vector<Eigen::Vector3d>& points,
                              const std::vector<std::vector<Index>>& polys) {
  HalfEdgeMesh m;
  std::string error;
  EXPECT_TRUE(HalfEdgeMesh::from_polygons(points, polys, m, &error)) << error;
  return m;
}

// Box [lo, hi]. Vertices: bit 0 of the index picks x (0 lo, 1 hi) as in the
// unit cube 0 (0,0,0) 1 (1,0,0) 2 (1,1,0) 3 (0,1,0) 4 (0,0,1) 5 (1,0,1)
// 6 (1,1,1) 7 (0,1,1). Faces: 0 bottom (-z), 1 top (+z), 2 front (-y),
// 3 back (+y), 4 left (-x), 5 right (+x).
enum BoxFace : Index { kBottom = 0, kTop, kFront, kBack, kLeft, kRight };

inline std::vector<std::vector<Index>> box_polygons() {
  return {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 4, 7, 3}, {1, 2, 6, 5}};
}

inline std::vector<Eigen::Vector3d> box_points(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return {{lo.x(), lo.y(), lo.z()}, {hi.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), lo.z()}, {lo.x(), hi.y(), lo.z()},
          {lo.x(), lo.y(), hi.z()}, {hi.x(), lo.y(), hi.z()}, {hi.x(), hi.y(), hi.z()}, {lo.x(), hi.y(), hi.z()}};
}

inline HalfEdgeMesh make_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return mesh_from(box_points(lo, hi), box_polygons());
}

inline HalfEdgeMesh unit_cube() { return make_box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()); }

// Tetrahedron a b c d, wound outward whatever the order of the points.
inline HalfEdgeMesh make_tetrahedron(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                     const Eigen::Vector3d& d) {
  const bool positive = (b - a).cross(c - a).dot(d - a) > 0;  // d above (a, b, c)
  std::vector<std::vector<Index>> polys = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  if (!positive)
    for (auto& p : polys) std::reverse(p.begin(), p.end());
  return mesh_from({a, b, c, d}, polys);
}

// Prism over the polygon `base` (counter-clockwise in the xy-plane seen from
// +z) from z = z0 to z = z1. Vertices: base i at z0 is i, at z1 is n + i.
// Faces: 0 bottom, 1 top, 2 + i the side over base edge i -> i+1.
inline HalfEdgeMesh make_prism(const std::vector<Eigen::Vector2d>& base, double z0, double z1) {
  const Index n = static_cast<Index>(base.size());
  std::vector<Eigen::Vector3d> pts;
  for (Index i = 0; i < n; ++i) pts.emplace_back(base[i].x(), base[i].y(), z0);
  for (Index i = 0; i < n; ++i) pts.emplace_back(base[i].x(), base[i].y(), z1);
  std::vector<std::vector<Index>> polys(2);
  for (Index i = 0; i < n; ++i) polys[0].push_back(n - 1 - i);
  for (Index i = 0; i < n; ++i) polys[1].push_back(n + i);
  for (Index i = 0; i < n; ++i) polys.push_back({i, (i + 1) % n, n + (i + 1) % n, n + i});
  return mesh_from(pts, polys);
}

// Regular n-gon (circumradius r, first vertex at angle `phase`), centred at c.
inline std::vector<Eigen::Vector2d> regular_polygon(int n, double r, const Eigen::Vector2d& c = Eigen::Vector2d::Zero(),
                                                    double phase = 0.0) {
  std::vector<Eigen::Vector2d> out;
  for (int i = 0; i < n; ++i) {
    const double a = phase + 2.0 * M_PI * i / n;
    out.push_back(c + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return out;
}

// Bipyramid over the convex polygon `base` (in the plane z = 0) with apexes at
// heights top and -bottom (top, bottom > 0) over the base's vertex average,
// which is inside the base. Vertices: the base, then the top and bottom
// apexes.
inline HalfEdgeMesh make_bipyramid(const std::vector<Eigen::Vector2d>& base, double top, double bottom) {
  const Index n = static_cast<Index>(base.size());
  std::vector<Eigen::Vector3d> pts;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& p : base) {
    pts.emplace_back(p.x(), p.y(), 0.0);
    c += p / n;
  }
  pts.emplace_back(c.x(), c.y(), top);
  pts.emplace_back(c.x(), c.y(), -bottom);
  std::vector<std::vector<Index>> polys;
  for (Index i = 0; i < n; ++i) {
    polys.push_back({i, (i + 1) % n, n});
    polys.push_back({(i + 1) % n, i, n + 1});
  }
  return mesh_from(pts, polys);
}

// Flat, two-sided polygon: face 0 is `points` in order (counter-clockwise
// seen from the side its normal points to), face 1 the same ring reversed.
inline HalfEdgeMesh make_flat_polygon(const std::vector<Eigen::Vector3d>& points) {
  std::vector<Index> ring;
  for (Index i = 0; i < points.size(); ++i) ring.push_back(i);
  std::vector<Index> back(ring.rbegin(), ring.rend());
  return mesh_from(points, {ring, back});
}

// A point or segment hull (vertices only), as the builder stores them.
inline HalfEdgeMesh make_vertices_only(const std::vector<Eigen::Vector3d>& points, double tolerance) {
  HalfEdgeMesh m;
  for (const auto& p : points) m.vertices.push_back({p, kInvalidIndex});
  m.set_tolerance(tolerance);
  return m;
}

// Convex polygon with n vertices on an ellipse at sorted random angles, each
// gap at least a fifth of the even spacing (so no two points nearly meet).
inline std::vector<Eigen::Vector2d> random_convex_polygon(std::mt19937_64& rng, int n, double rx, double ry) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> gaps(n);
  double total = 0;
  for (auto& g : gaps) total += (g = 0.2 + u(rng));
  std::vector<Eigen::Vector2d> out;
  double a = 2.0 * M_PI * u(rng);
  for (int i = 0; i < n; ++i) {
    out.emplace_back(rx * std::cos(a), ry * std::sin(a));
    a += 2.0 * M_PI * gaps[i] / total;
  }
  return out;
}

// The same mesh moved by `offset`, rebuilt so that planes and tolerance are
// those of the moved positions.
inline HalfEdgeMesh translated(const HalfEdgeMesh& m, const Eigen::Vector3d& offset) {
  std::vector<Eigen::Vector3d> pts;
  for (const auto& v : m.vertices) pts.push_back(v.position + offset);
  return mesh_from(pts, m.polygons());
}

// A random convex solid: a prism or a bipyramid over a random convex polygon
// with 3..12 vertices, of size around `scale`, translated by `offset`.
inline HalfEdgeMesh random_convex_solid(std::mt19937_64& rng, double scale = 1.0,
                                        const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) {
  std::uniform_real_distribution<double> u(0.3, 1.0);
  std::uniform_int_distribution<int> sides(3, 12);
  const int n = sides(rng);
  const auto base = random_convex_polygon(rng, n, scale * u(rng), scale * u(rng));
  HalfEdgeMesh m = rng() % 2 == 0 ? make_prism(base, -scale * u(rng), scale * u(rng))
                                  : make_bipyramid(base, scale * u(rng), scale * u(rng));
  return offset.isZero() ? m : translated(m, offset);
}

}  // namespace hedra::hull::test
