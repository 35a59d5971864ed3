// The exact reference: see exact_reference.hpp for the method. Nothing here
// calls hedra's GJK, EPA or support mappings; the support functions of the
// cores are written out below from the shapes' definitions.
#include "exact_reference.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <qhull_reference.hpp>
#include <queue>
#include <utility>
#include <variant>

namespace hedra::reference {
namespace {

using Vec = Eigen::Vector3d;
using collision::Pose;
using collision::Shape;

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kPi = 3.14159265358979323846;
constexpr double kUniqueAngle = 1e-8;  // candidate normals closer than this are one normal

// A shape's core placed in the pair's recentred frame: its points, its radius
// and (for the bounds) its exact support function.
struct Core {
  enum class Kind { points, segment, box, cylinder, cone } kind = Kind::points;
  std::vector<Vec> points;  // recentred world frame
  double radius = 0.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Vec translation = Vec::Zero();  // recentred
  Vec half_extents = Vec::Zero();
  double half_length = 0.0;
  double core_radius = 0.0;  // cylinder / cone radius

  bool curved() const { return kind == Kind::cylinder || kind == Kind::cone; }

  // h(n) = max over the true core of n . x.
  double support_value(const Vec& n) const {
    const Vec d = rotation.transpose() * n;
    const double rho = std::hypot(d.x(), d.y());
    double local = 0.0;
    switch (kind) {
      case Kind::points: {
        double best = -std::numeric_limits<double>::infinity();
        for (const Vec& p : points) best = std::max(best, n.dot(p));
        return best;
      }
      case Kind::segment:
        local = half_length * std::abs(d.z());
        break;
      case Kind::box:
        local = half_extents.cwiseProduct(d.cwiseAbs()).sum();
        break;
      case Kind::cylinder:
        local = core_radius * rho + half_length * std::abs(d.z());
        break;
      case Kind::cone:
        local = std::max(half_length * d.z(), -half_length * d.z() + core_radius * rho);
        break;
    }
    return local + n.dot(translation);
  }

  // A point of the true core maximising n . x (any kind of core; ties go
  // to +axis, a cap's centre when n is along a cylinder's or cone's axis).
  Vec support_point(const Vec& n) const {
    if (kind == Kind::points) {
      std::size_t best = 0;
      for (std::size_t i = 1; i < points.size(); ++i)
        if (n.dot(points[i]) > n.dot(points[best])) best = i;
      return points[best];
    }
    const Vec d = rotation.transpose() * n;
    auto sign = [](double x) { return x >= 0.0 ? 1.0 : -1.0; };
    const double rho = std::hypot(d.x(), d.y());
    const double cx = rho > 0.0 ? core_radius * d.x() / rho : 0.0;
    const double cy = rho > 0.0 ? core_radius * d.y() / rho : 0.0;
    Vec local;
    if (kind == Kind::segment) {
      local = Vec(0.0, 0.0, sign(d.z()) * half_length);
    } else if (kind == Kind::box) {
      local = Vec(sign(d.x()) * half_extents.x(), sign(d.y()) * half_extents.y(), sign(d.z()) * half_extents.z());
    } else if (kind == Kind::cylinder) {
      local = Vec(cx, cy, sign(d.z()) * half_length);
    } else {
      local = half_length * d.z() >= -half_length * d.z() + core_radius * rho ? Vec(0.0, 0.0, half_length)
                                                                              : Vec(cx, cy, -half_length);
    }
    return rotation * local + translation;
  }
};

// The core of `shape` posed by (rotation, translation) where translation is
// already relative to the pair's centre.
Core make_core(const Shape& shape, const Eigen::Matrix3d& rotation, const Vec& translation, int sides,
               const std::vector<Vec>* override_points) {
  Core core;
  core.rotation = rotation;
  core.translation = translation;
  auto place = [&](const Vec& local) { core.points.push_back(rotation * local + translation); };
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, collision::Sphere>) {
          core.kind = Core::Kind::points;
          core.radius = s.radius + s.margin;
          place(Vec::Zero());
        } else if constexpr (std::is_same_v<T, collision::Capsule>) {
          core.kind = Core::Kind::segment;
          core.radius = s.radius + s.margin;
          core.half_length = s.half_length;
          place(Vec(0, 0, -s.half_length));
          place(Vec(0, 0, s.half_length));
        } else if constexpr (std::is_same_v<T, collision::Box>) {
          core.kind = Core::Kind::box;
          core.radius = s.margin;
          core.half_extents = s.half_extents;
          for (int k = 0; k < 8; ++k)
            place(Vec(k & 1 ? s.half_extents.x() : -s.half_extents.x(),
                      k & 2 ? s.half_extents.y() : -s.half_extents.y(),
                      k & 4 ? s.half_extents.z() : -s.half_extents.z()));
        } else if constexpr (std::is_same_v<T, collision::Cylinder> || std::is_same_v<T, collision::Cone>) {
          const bool cylinder = std::is_same_v<T, collision::Cylinder>;
          core.kind = cylinder ? Core::Kind::cylinder : Core::Kind::cone;
          core.radius = s.margin;
          core.half_length = s.half_length;
          core.core_radius = s.radius;
          if (!cylinder) place(Vec(0, 0, s.half_length));
          for (int k = 0; k < sides; ++k) {
            const double angle = 2.0 * kPi * k / sides;
            const double x = s.radius * std::cos(angle), y = s.radius * std::sin(angle);
            place(Vec(x, y, -s.half_length));
            if (cylinder) place(Vec(x, y, s.half_length));
          }
        } else {  // Polyhedron
          core.kind = Core::Kind::points;
          core.radius = s.margin;
          if (override_points) {
            for (const Vec& p : *override_points) place(p);
          } else {
            for (const Vec& v : s.hull->vertices()) place(s.hull->offset() + v);
          }
        }
      },
      shape);
  return core;
}

// ---- the core difference ----------------------------------------------------

struct CoreAnswer {
  bool ok = false;
  std::string reason;
  double sd = 0.0;  // signed distance of the core difference
  Vec normal = Vec::UnitZ();
  bool unique = false;
  double spread = 0.0;
  Vec point_a = Vec::Zero();
  Vec point_b = Vec::Zero();
  int dimension = 3;
  double flattening = 0.0;  // thickness neglected by a lower-dimensional computation
  double tolerance = 0.0;
  std::size_t points = 0;
};

// Closest point to the origin on triangle (a, b, c), by the Voronoi regions
// of its vertices, edges and face; returns barycentric weights.
std::array<double, 3> closest_on_triangle(const Vec& a, const Vec& b, const Vec& c) {
  const Vec ab = b - a, ac = c - a, ap = -a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Vec bp = -b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double t = d1 / (d1 - d3);
    return {1 - t, t, 0};
  }
  const Vec cp = -c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double t = d2 / (d2 - d6);
    return {1 - t, 0, t};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - t, t};
  }
  const double den = va + vb + vc;
  if (!(den > 0)) {  // degenerate triangle: best of its edges
    const double tab = std::clamp(d1 / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
    return {1 - tab, tab, 0};
  }
  const double v = vb / den, w = vc / den;
  return {1 - v - w, v, w};
}

// Barycentric coordinates of x in triangle (a, b, c) (projected on its plane).
std::array<double, 3> barycentric(const Vec& x, const Vec& a, const Vec& b, const Vec& c) {
  const Vec n = (b - a).cross(c - a);
  const double nn = n.squaredNorm();
  if (!(nn > 0)) return {-1, -1, -1};
  const double u = n.dot((c - b).cross(x - b)) / nn;
  const double v = n.dot((a - c).cross(x - c)) / nn;
  return {u, v, 1 - u - v};
}

struct Diff {
  const std::vector<Vec>& a;
  const std::vector<Vec>& b;
  std::vector<Vec> d;
  explicit Diff(const std::vector<Vec>& pa, const std::vector<Vec>& pb) : a(pa), b(pb) {
    d.reserve(a.size() * b.size());
    for (const Vec& p : a)
      for (const Vec& q : b) d.push_back(p - q);
  }
  const Vec& point_a(std::size_t k) const { return a[k / b.size()]; }
  const Vec& point_b(std::size_t k) const { return b[k % b.size()]; }
};

void set_witness(CoreAnswer& out, const Diff& diff, std::initializer_list<std::pair<std::size_t, double>> weights) {
  out.point_a = Vec::Zero();
  out.point_b = Vec::Zero();
  for (const auto& [k, w] : weights) {
    out.point_a += w * diff.point_a(k);
    out.point_b += w * diff.point_b(k);
  }
}

Vec any_perpendicular(const Vec& u) {
  const Vec t = std::abs(u.x()) < 0.6 ? Vec::UnitX() : Vec::UnitY();
  return (t - u * u.dot(t)).normalized();
}

void segment_case(CoreAnswer& out, const Diff& diff, std::size_t k0, std::size_t k1) {
  const Vec& p = diff.d[k0];
  const Vec e = diff.d[k1] - p;
  const double ee = e.squaredNorm();
  const double t = ee > 0 ? std::clamp(-p.dot(e) / ee, 0.0, 1.0) : 0.0;
  const Vec v = p + t * e;
  out.sd = v.norm();
  set_witness(out, diff, {{k0, 1 - t}, {k1, t}});
  if (out.sd > out.tolerance) {
    out.normal = -v / out.sd;
    out.unique = true;
  } else {
    out.normal = ee > 0 ? any_perpendicular(e.normalized()) : Vec::UnitZ();
    out.unique = false;
  }
}

// D flat: the plane through p0 with unit normal m and in-plane basis u, w.
void flat_case(CoreAnswer& out, const Diff& diff, const Vec& p0, const Vec& u, const Vec& w, const Vec& m) {
  const std::size_t n = diff.d.size();
  std::vector<std::pair<Eigen::Vector2d, std::size_t>> pts(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec r = diff.d[k] - p0;
    pts[k] = {Eigen::Vector2d(r.dot(u), r.dot(w)), k};
  }
  std::sort(pts.begin(), pts.end(), [](const auto& x, const auto& y) {
    return x.first.x() < y.first.x() || (x.first.x() == y.first.x() && x.first.y() < y.first.y());
  });
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  // Andrew's monotone chain, counter-clockwise in (u, w).
  std::vector<std::pair<Eigen::Vector2d, std::size_t>> hull(2 * n);
  std::size_t h = 0;
  for (std::size_t i = 0; i < n; ++i) {
    while (h >= 2 && cross(hull[h - 2].first, hull[h - 1].first, pts[i].first) <= 0) --h;
    hull[h++] = pts[i];
  }
  for (std::size_t i = n - 1, lower = h + 1; i-- > 0;) {
    while (h >= lower && cross(hull[h - 2].first, hull[h - 1].first, pts[i].first) <= 0) --h;
    hull[h++] = pts[i];
  }
  hull.resize(h > 1 ? h - 1 : h);
  if (hull.size() < 3) {  // collinear after all: the segment between the extremes
    segment_case(out, diff, pts.front().second, pts.back().second);
    return;
  }
  const Eigen::Vector2d o(-p0.dot(u), -p0.dot(w));
  const double height = -p0.dot(m);  // the origin is p0 + o.x u + o.y w + height m
  bool inside = true;
  for (std::size_t i = 0; i < hull.size(); ++i)
    if (cross(hull[i].first, hull[(i + 1) % hull.size()].first, o) < 0) inside = false;
  if (inside) {
    // The fan triangle holding o gives the witness weights.
    double best_min = -std::numeric_limits<double>::infinity();
    std::array<double, 3> best_w{1, 0, 0};
    std::size_t best_t = 1;
    for (std::size_t t = 1; t + 1 < hull.size(); ++t) {
      const Eigen::Vector2d a = hull[0].first, b = hull[t].first, c = hull[t + 1].first;
      const double area = cross(a, b, c);
      if (!(area > 0)) continue;
      const std::array<double, 3> wts{cross(b, c, o) / area, cross(c, a, o) / area, cross(a, b, o) / area};
      const double mn = std::min({wts[0], wts[1], wts[2]});
      if (mn > best_min) {
        best_min = mn;
        best_w = wts;
        best_t = t;
      }
    }
    set_witness(out, diff,
                {{hull[0].second, best_w[0]}, {hull[best_t].second, best_w[1]}, {hull[best_t + 1].second, best_w[2]}});
    out.sd = std::abs(height);
    if (out.sd > out.tolerance) {
      out.normal = height > 0 ? m : Vec(-m);
      out.unique = true;
    } else {
      out.normal = m;  // +m and -m both attain the minimum
      out.unique = false;
    }
    return;
  }
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_i = 0;
  double best_t = 0;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Vec& p = diff.d[hull[i].second];
    const Vec e = diff.d[hull[(i + 1) % hull.size()].second] - p;
    const double ee = e.squaredNorm();
    const double t = ee > 0 ? std::clamp(-p.dot(e) / ee, 0.0, 1.0) : 0.0;
    const double dist = (p + t * e).norm();
    if (dist < best) {
      best = dist;
      best_i = i;
      best_t = t;
    }
  }
  segment_case(out, diff, hull[best_i].second, hull[(best_i + 1) % hull.size()].second);
  (void)best_t;
}

void solid_case(CoreAnswer& out, const Diff& diff) {
  const QhullHull h = qhull_hull(diff.d, "Qt");
  if (!h.ok) {
    out.ok = false;
    out.reason =
        "qhull failed on the Minkowski difference (" + std::to_string(diff.d.size()) + " points): " + h.messages;
    return;
  }
  const std::size_t nt = h.triangles.size();
  std::size_t best_f = 0;
  for (std::size_t f = 1; f < nt; ++f)
    if (h.triangle_planes[f][3] > h.triangle_planes[best_f][3]) best_f = f;
  const double max_offset = h.triangle_planes[best_f][3];

  bool separated_normal = false;
  if (max_offset > 0) {
    // Outside: the closest point lies on a facet whose plane has the origin in front.
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < nt; ++f) {
      if (!(h.triangle_planes[f][3] > 0)) continue;
      const auto& t = h.triangles[f];
      const std::array<double, 3> wts = closest_on_triangle(diff.d[t[0]], diff.d[t[1]], diff.d[t[2]]);
      const Vec v = wts[0] * diff.d[t[0]] + wts[1] * diff.d[t[1]] + wts[2] * diff.d[t[2]];
      const double dist = v.norm();
      if (dist < best) {
        best = dist;
        // Inside the facet's face region the facet's own plane normal (from
        // qhull, accurate to rounding of D's size) is the normal; -v/|v|
        // loses eps * size / |v| of angle when |v| is small.
        // On a shared edge of a merged facet's triangles the two agree to
        // within that rounding: the plane normal is taken then too.
        const Vec plane_normal = h.triangle_planes[f].head<3>();
        const bool face_region = (wts[0] > 0 && wts[1] > 0 && wts[2] > 0) ||
                                 (dist > 0 && (v / dist + plane_normal).norm() * dist <= out.tolerance);
        out.normal = face_region ? plane_normal : dist > 0 ? Vec(-v / dist) : Vec::UnitZ();
        set_witness(out, diff, {{std::size_t(t[0]), wts[0]}, {std::size_t(t[1]), wts[1]}, {std::size_t(t[2]), wts[2]}});
      }
    }
    out.sd = best;
    separated_normal = best > out.tolerance;
  } else {
    out.sd = max_offset;
  }
  if (separated_normal) {
    out.unique = true;
    out.spread = 0.0;
    return;
  }
  // Touching or inside: the nearest facet planes decide.
  const Vec n_best = h.triangle_planes[best_f].head<3>();
  out.spread = 0.0;
  double best_min = -std::numeric_limits<double>::infinity();
  std::size_t witness_f = best_f;
  std::array<double, 3> witness_w{1.0 / 3, 1.0 / 3, 1.0 / 3};
  const Vec x = -max_offset * n_best;  // the origin's projection on the best plane
  for (std::size_t f = 0; f < nt; ++f) {
    if (h.triangle_planes[f][3] < max_offset - out.tolerance) continue;
    const Vec n = h.triangle_planes[f].head<3>();
    const double angle = std::atan2(n.cross(n_best).norm(), n.dot(n_best));
    out.spread = std::max(out.spread, angle);
    if (angle > kUniqueAngle) continue;
    const auto& t = h.triangles[f];
    const std::array<double, 3> wts = barycentric(x, diff.d[t[0]], diff.d[t[1]], diff.d[t[2]]);
    const double mn = std::min({wts[0], wts[1], wts[2]});
    if (mn > best_min) {
      best_min = mn;
      witness_f = f;
      witness_w = wts;
    }
  }
  out.normal = n_best;
  out.unique = out.spread <= kUniqueAngle;
  if (max_offset <= 0) {
    const auto& t = h.triangles[witness_f];
    set_witness(
        out, diff,
        {{std::size_t(t[0]), witness_w[0]}, {std::size_t(t[1]), witness_w[1]}, {std::size_t(t[2]), witness_w[2]}});
  }
}

CoreAnswer core_distance(const std::vector<Vec>& a, const std::vector<Vec>& b) {
  CoreAnswer out;
  out.ok = true;
  const Diff diff(a, b);
  const std::vector<Vec>& d = diff.d;
  out.points = d.size();
  double size = 0.0;
  for (const Vec& p : d) size = std::max(size, p.cwiseAbs().maxCoeff());
  const Vec p0 = d[0];
  std::size_t i1 = 0;
  double extent = 0.0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    const double r = (d[k] - p0).norm();
    if (r > extent) {
      extent = r;
      i1 = k;
    }
  }
  out.tolerance = 64 * kEps * std::max(size, extent);
  if (extent <= out.tolerance) {
    out.dimension = 0;
    out.flattening = extent;
    segment_case(out, diff, 0, 0);
    return out;
  }
  const Vec u = (d[i1] - p0) / extent;
  std::size_t i2 = 0;
  double width = 0.0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    const Vec r = d[k] - p0;
    const double off = (r - u * u.dot(r)).norm();
    if (off > width) {
      width = off;
      i2 = k;
    }
  }
  if (width <= out.tolerance) {
    out.dimension = 1;
    out.flattening = width;
    std::size_t kmin = 0, kmax = 0;
    for (std::size_t k = 0; k < d.size(); ++k) {
      const double s = u.dot(d[k] - p0);
      if (s < u.dot(d[kmin] - p0)) kmin = k;
      if (s > u.dot(d[kmax] - p0)) kmax = k;
    }
    segment_case(out, diff, kmin, kmax);
    return out;
  }
  const Vec m = u.cross(d[i2] - p0).normalized();
  double thickness = 0.0;
  for (const Vec& p : d) thickness = std::max(thickness, std::abs(m.dot(p - p0)));
  if (thickness <= out.tolerance) {
    out.dimension = 2;
    out.flattening = thickness;
    const Vec w = m.cross(u);
    flat_case(out, diff, p0, u, w, m);
    return out;
  }
  out.dimension = 3;
  solid_case(out, diff);
  return out;
}

// Cores of revolution with nearly parallel axes (segments, cylinders,
// cones, single points): a bracket of the cores' signed distance from the
// meridian section. With both axes along k, D = A - B is a solid of
// revolution whose section (radial, axial) is the convex hull of the sums
// of A's section points and -B's, and the origin's signed distance to D is
// the 2D signed distance of its (radial, axial) position to that polygon.
// The axes are parallel only to an angle theta: the core with the smaller
// bounding radius R, turned about its centre onto the other's axis, moves
// by at most theta R, so the true value is within theta R of the parallel
// pair's. (hedra's revolution.hpp reduces the same way; this is a separate
// implementation: the polygon by brute force over point pairs.) Returns
// false when a core is not of revolution or neither is curved.
bool meridian_bracket(const Core& a, const Core& b, double& lower, double& upper) {
  auto section = [](const Core& c, std::vector<Eigen::Vector2d>& out, double& bounding) {
    out.clear();
    switch (c.kind) {
      case Core::Kind::segment:
        out = {{0.0, -c.half_length}, {0.0, c.half_length}};
        bounding = c.half_length;
        return true;
      case Core::Kind::cylinder:
        for (const double x : {-c.core_radius, c.core_radius})
          for (const double y : {-c.half_length, c.half_length}) out.emplace_back(x, y);
        bounding = std::hypot(c.core_radius, c.half_length);
        return true;
      case Core::Kind::cone:
        out = {{-c.core_radius, -c.half_length}, {c.core_radius, -c.half_length}, {0.0, c.half_length}};
        bounding = std::hypot(c.core_radius, c.half_length);
        return true;
      case Core::Kind::points:
        if (c.points.size() != 1) return false;
        out = {{0.0, 0.0}};
        bounding = 0.0;
        return true;
      default:
        return false;
    }
  };
  std::vector<Eigen::Vector2d> sa, sb;
  double ra = 0.0, rb = 0.0;
  if (!(a.curved() || b.curved()) || !section(a, sa, ra) || !section(b, sb, rb)) return false;
  // Centres: a point core's only point; the others' translation.
  const Vec ca = a.kind == Core::Kind::points ? a.points[0] : a.translation;
  const Vec cb = b.kind == Core::Kind::points ? b.points[0] : b.translation;
  const bool a_free = a.kind == Core::Kind::points, b_free = b.kind == Core::Kind::points;
  const Vec ka = a.rotation.col(2), kb = b.rotation.col(2);
  // The reference axis: that of the core with the larger bounding radius
  // (the other one is turned).
  const bool along_a = b_free || (!a_free && ra >= rb);
  const Vec k = along_a ? ka : kb;
  const double sign_a = a_free || k.dot(ka) >= 0.0 ? 1.0 : -1.0;
  const double sign_b = b_free || k.dot(kb) >= 0.0 ? 1.0 : -1.0;
  const Vec& turned = along_a ? kb : ka;
  const bool turned_free = along_a ? b_free : a_free;
  const double theta = turned_free ? 0.0 : std::atan2(k.cross(turned).norm(), std::abs(k.dot(turned)));
  const double tilt = theta * (along_a ? rb : ra);
  std::vector<Eigen::Vector2d> d;
  for (const auto& p : sa)
    for (const auto& q : sb) d.emplace_back(p.x() + q.x(), sign_a * p.y() - sign_b * q.y());
  const Vec q3 = cb - ca;  // the origin, relative to D's axis through ca - cb
  const double z0 = q3.dot(k);
  const Eigen::Vector2d q((q3 - z0 * k).norm(), z0);
  double size = q.norm();
  for (const auto& p : d) size = std::max(size, p.norm());
  const double tol = 64 * kEps * size;
  double inside = -std::numeric_limits<double>::infinity();
  double outside = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < d.size(); ++i) {
    for (std::size_t j = 0; j < d.size(); ++j) {
      const Eigen::Vector2d e = d[j] - d[i];
      const double len = e.norm();
      if (!(len > tol)) continue;
      const Eigen::Vector2d m(e.y() / len, -e.x() / len);
      bool supporting = true;
      for (const auto& p : d) supporting = supporting && m.dot(p - d[i]) <= tol;
      if (!supporting) continue;
      inside = std::max(inside, m.dot(q - d[i]));
      const double t = std::clamp((q - d[i]).dot(e) / (len * len), 0.0, 1.0);
      outside = std::min(outside, (d[i] + t * e - q).norm());
    }
  }
  if (!std::isfinite(inside)) return false;
  const double sd = inside > 0.0 ? outside : inside;
  lower = sd - tilt - tol;
  upper = sd + tilt + tol;
  return std::isfinite(lower) && std::isfinite(upper);
}

// Cutting planes on the difference's own support points, for overlapping
// curved pairs whose bracket stays wide (nearly coaxial cores tilted by more
// than the meridian bracket allows: at 1e-4 rad it is 2e-4 of the size wide,
// and the inscribed polygons of A and B, refined around one normal at a
// time, do not resolve a ring of nearly equal depths). Every point
// s_D(n) = s_A(n) - s_B(-n) lies in D, so the hull P of such points is
// inside D and the origin's depth in P (qhull: the nearest facet plane) is
// at most its depth in D: -depth_P bounds the signed distance from above.
// Every sampled direction gives h_D(n) >= depth_D exactly (closed-form
// support values): -min h_D(n_k) bounds it from below. A facet of P whose
// plane lies below the best h_D(n_k) by more than the target is cut off by
// the support point along its own normal (which lies h_D(n_f) - h_P(n_f) > 0
// beyond it), so the passes add, per facet, the one point that removes it:
// Kelley's cutting planes over all the low facets at once, from a Fibonacci
// sphere of directions. Fails (returns false) when the origin is not inside
// P: separated and touching pairs have a unique nearest point, which the
// polygons resolve.
struct SupportHull {
  bool ok = false;
  double lower = 0.0, upper = 0.0;  // bracket of the cores' signed distance
  Vec normal = Vec::UnitZ();        // the nearest facet's outward normal
  Vec point_a = Vec::Zero();        // witnesses on the inscribed hull's facet
  Vec point_b = Vec::Zero();
  std::size_t points = 0;
  int passes = 0;
};

SupportHull support_hull_bracket(const Core& a, const Core& b, double target, std::size_t max_points) {
  SupportHull out;
  std::vector<Vec> d, pa, pb;
  double best = std::numeric_limits<double>::infinity();  // min h_D over the directions sampled
  double size = 0.0;
  auto add = [&](const Vec& n) {
    best = std::min(best, a.support_value(n) + b.support_value(-n));
    pa.push_back(a.support_point(n));
    pb.push_back(b.support_point(-n));
    d.push_back(pa.back() - pb.back());
    size = std::max(size, d.back().norm());
  };
  constexpr int kSphere = 1024;
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < kSphere; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / kSphere, r = std::sqrt(std::max(0.0, 1.0 - z * z));
    add(Vec(r * std::cos(golden * i), r * std::sin(golden * i), z));
  }
  for (const Vec& k : {Vec(a.rotation.col(2)), Vec(b.rotation.col(2))}) {
    add(k);
    add(-k);
  }
  std::vector<std::pair<double, Vec>> low;
  for (int pass = 0; pass < 64; ++pass) {
    const QhullHull h = qhull_hull(d, "Qt");
    if (!h.ok) return out;
    std::size_t nearest = 0;
    for (std::size_t f = 1; f < h.triangles.size(); ++f)
      if (h.triangle_planes[f][3] > h.triangle_planes[nearest][3]) nearest = f;
    const double max_offset = h.triangle_planes[nearest][3];  // -depth_P
    if (!(max_offset < 0.0)) return out;
    const double rounding = 64 * kEps * size + std::max(0.0, h.max_outside);
    out.ok = true;
    out.passes = pass + 1;
    out.points = d.size();
    out.lower = -best;
    out.upper = std::max(max_offset + rounding, out.lower);
    out.normal = h.triangle_planes[nearest].head<3>();
    const auto& t = h.triangles[nearest];
    const Vec x = -max_offset * out.normal;  // the origin's projection on the facet
    const std::array<double, 3> w = barycentric(x, d[t[0]], d[t[1]], d[t[2]]);
    out.point_a = w[0] * pa[t[0]] + w[1] * pa[t[1]] + w[2] * pa[t[2]];
    out.point_b = w[0] * pb[t[0]] + w[1] * pb[t[1]] + w[2] * pb[t[2]];
    if (out.upper - out.lower <= target || d.size() >= max_points) break;
    // The facets below best - target/2, lowest first; merged facets'
    // triangles share a plane and are cut once.
    low.clear();
    for (std::size_t f = 0; f < h.triangles.size(); ++f)
      if (-h.triangle_planes[f][3] < best - 0.5 * target)
        low.emplace_back(-h.triangle_planes[f][3], h.triangle_planes[f].head<3>());
    std::sort(low.begin(), low.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    const std::size_t before = d.size();
    for (std::size_t i = 0; i < low.size() && d.size() < max_points; ++i)
      if (i == 0 || low[i].second != low[i - 1].second) add(low[i].second);
    if (d.size() == before) break;
  }
  return out;
}

// A curved core (cylinder, cone) against a core of finitely many points
// (box, hull, segment): a peg in a hole. With the curved core's
// centre c and axis k (as h_D sees it: k = a for A, -b for B) and the other
// core's points moved to q_j (c - b_j for a curved A, a_j - c for a curved
// B), h_D(n) = f(k . n) + max_j q_j . n, f the curved core's profile (the
// support function of its meridian section: (r, +-h) for a cylinder, (0, h)
// and (r, -h) for a cone). In the meridian half-plane of azimuth phi, n =
// cos(theta) k + sin(theta) u(phi), theta in [0, pi], h_D is the 2D support
// function of the points (section radial + q_j . u(phi), section axial +
// q_j . k) in the direction (sin theta, cos theta): its minimum G(phi) over
// theta comes from their convex hull's right side (gift wrapping from the
// lowest point, both poles, a vertex's own minimum where the origin is
// outside). Each point's radial coordinate moves with phi at most at the
// rate L = max_j |q_j perp|, and h_D grows with it (sin theta >= 0): over
// [phi - w, phi + w], G is at least the minimum at phi with every point
// lowered by L w (exact at the poles, where sin theta = 0); best first
// over intervals of phi until every interval is within the target of the
// best value found, or the budget (then the bracket is as wide as it is).
// Upper bound of the depth: h_D (closed forms) at the best direction.
// (hedra's revolution_polytope.hpp reduces the same way; this is a separate
// implementation: hull by gift wrapping, a uniform Lipschitz lowering
// instead of each sinusoid's minimum.) Returns false when the pair is not of
// that kind.
struct MeridianPoints {
  Vec k, e1, e2;
  std::vector<Vec> q;
  std::vector<Eigen::Vector2d> section;  // (radial, axial) of the curved core's right half
  double lipschitz = 0.0;
};

// min over theta of the 2D support function of the points at azimuth phi;
// `direction` gets the minimiser (sin theta, cos theta).
// With every point's radial coordinate lowered by `shift`.
double meridian_minimum(const MeridianPoints& m, double phi, double shift, Eigen::Vector2d& direction) {
  const Vec u = std::cos(phi) * m.e1 + std::sin(phi) * m.e2;
  std::vector<Eigen::Vector2d> p;
  for (const Vec& q : m.q)
    for (const Eigen::Vector2d& s : m.section) p.emplace_back(s.x() + q.dot(u) - shift, s.y() + q.dot(m.k));
  std::size_t low = 0, high = 0;
  for (std::size_t i = 1; i < p.size(); ++i) {
    if (p[i].y() < p[low].y() || (p[i].y() == p[low].y() && p[i].x() > p[low].x())) low = i;
    if (p[i].y() > p[high].y()) high = i;
  }
  double best = -p[low].y();
  direction = Eigen::Vector2d(0.0, -1.0);
  if (p[high].y() < best) {
    best = p[high].y();
    direction = Eigen::Vector2d(0.0, 1.0);
  }
  const auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
  Eigen::Vector2d normal_in(0.0, -1.0);
  std::size_t at = low;
  for (std::size_t step = 0; step <= p.size(); ++step) {
    // The next vertex: every point on the left of at -> next (the farthest
    // of collinear ones).
    std::size_t next = at;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p[i] == p[at]) continue;
      if (next == at) {
        next = i;
        continue;
      }
      const double c = cross(p[next] - p[at], p[i] - p[at]);
      if (c < 0.0 || (c == 0.0 && (p[i] - p[at]).norm() > (p[next] - p[at]).norm())) next = i;
    }
    Eigen::Vector2d normal_out(0.0, 1.0);
    const Eigen::Vector2d e = p[next] - p[at];
    const bool climbs = next != at && e.y() >= 0.0 && p[at].y() < p[high].y();
    if (climbs) normal_out = Eigen::Vector2d(e.y(), -e.x()) / e.norm();
    const double pn = p[at].norm();
    if (pn > 0.0) {  // the vertex's own minimum, where the origin is outside
      const Eigen::Vector2d w = -p[at] / pn;
      if (w.x() >= 0.0 && cross(normal_in, w) >= 0.0 && cross(w, normal_out) >= 0.0 && -pn < best) {
        best = -pn;
        direction = w;
      }
    }
    if (!climbs) break;
    const double value = normal_out.dot(p[at]);
    if (value < best) {
      best = value;
      direction = normal_out;
    }
    normal_in = normal_out;
    at = next;
  }
  return best;
}

bool azimuth_bracket(const Core& a, const Core& b, double target, int budget, double& lower, double& upper) {
  if (a.curved() == b.curved()) return false;
  const Core& curved = a.curved() ? a : b;
  const Core& other = a.curved() ? b : a;
  if (other.points.size() < 2) return false;  // a point: the meridian section is exact
  MeridianPoints m;
  m.k = a.curved() ? Vec(curved.rotation.col(2)) : Vec(-curved.rotation.col(2));
  m.e1 = any_perpendicular(m.k);
  m.e2 = m.k.cross(m.e1);
  for (const Vec& x : other.points) {
    m.q.push_back(a.curved() ? Vec(curved.translation - x) : Vec(x - curved.translation));
    m.lipschitz = std::max(m.lipschitz, (m.q.back() - m.q.back().dot(m.k) * m.k).norm());
  }
  const double r = curved.core_radius, h = curved.half_length;
  if (curved.kind == Core::Kind::cylinder)
    m.section = {{r, h}, {r, -h}};
  else
    m.section = {{0.0, h}, {r, -h}};
  double size = 0.0;
  for (const Vec& q : m.q) size = std::max(size, q.norm());
  const double rounding = 64 * kEps * (size + std::hypot(r, h));
  double best = std::numeric_limits<double>::infinity();
  const auto bound_at = [&](double phi, double w) {
    Eigen::Vector2d d;
    return meridian_minimum(m, phi, m.lipschitz * w, d) - rounding;
  };
  const auto value_at = [&](double phi) {
    Eigen::Vector2d d;
    meridian_minimum(m, phi, 0.0, d);
    const Vec n = d.y() * m.k + d.x() * (std::cos(phi) * m.e1 + std::sin(phi) * m.e2);
    const double h_d = a.support_value(n) + b.support_value(-n);  // closed forms
    best = std::min(best, h_d);
    return h_d;
  };
  using Interval = std::pair<double, std::pair<double, double>>;  // (bound, (centre, half width))
  std::priority_queue<Interval, std::vector<Interval>, std::greater<Interval>> open;
  constexpr int kStart = 256;
  for (int i = 0; i < kStart; ++i) {
    const double w = kPi / kStart, c = -kPi + (2 * i + 1) * w;
    value_at(c);
    open.push({bound_at(c, w), {c, w}});
  }
  int evaluations = kStart;
  while (!open.empty() && open.top().first < best - target && evaluations < budget) {
    const auto [c, w] = open.top().second;
    open.pop();
    for (const double side : {-0.5, 0.5}) {
      const double cc = c + side * w;
      value_at(cc);
      open.push({bound_at(cc, 0.5 * w), {cc, 0.5 * w}});
      ++evaluations;
    }
  }
  if (!open.empty() && std::isnan(open.top().first)) return false;
  // The depth lies in [least bound, best]; sd = -depth.
  lower = -best;
  upper = -std::min(open.top().first, best);
  return std::isfinite(lower) && std::isfinite(upper);
}

bool finite_points(const std::vector<Vec>& points) {
  for (const Vec& p : points)
    if (!p.allFinite()) return false;
  return true;
}

ExactResult fail(const std::string& reason) {
  ExactResult r;
  r.ok = false;
  r.reason = reason;
  return r;
}

}  // namespace

ExactResult exact_signed_distance(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                                  const ExactSettings& settings) {
  const collision::ShapeValidation va = collision::validate(a);
  if (!va.ok()) return fail("shape a: " + va.message);
  const collision::ShapeValidation vb = collision::validate(b);
  if (!vb.ok()) return fail("shape b: " + vb.message);
  if (!pose_a.finite() || !pose_b.finite()) return fail("a pose is not finite");
  if (settings.override_a && !finite_points(*settings.override_a)) return fail("points of a are not finite");
  if (settings.override_b && !finite_points(*settings.override_b)) return fail("points of b are not finite");

  const int sides = settings.polygon_sides > 0 ? settings.polygon_sides : 8;

  // The pair's centre: t_a + (t_b - t_a)/2; translations relative to it.
  const Vec half = 0.5 * (pose_b.translation - pose_a.translation);
  const Vec centre = pose_a.translation + half;
  Core core_a = make_core(a, pose_a.rotation, -half, sides, settings.override_a);
  Core core_b = make_core(b, pose_b.rotation, half, sides, settings.override_b);
  const double radius = core_a.radius + core_b.radius;
  const bool curved = core_a.curved() || core_b.curved();

  ExactResult out;
  out.curved = curved;
  out.polygon_sides = curved ? sides : 0;
  double upper = std::numeric_limits<double>::infinity();
  double lower = -std::numeric_limits<double>::infinity();
  double delta = sides > 0 ? kPi / sides : 0.0;
  Vec previous_normal = Vec::Zero();
  CoreAnswer kept;
  const double size = std::max(collision::bounding_radius(a), collision::bounding_radius(b));
  const int passes = curved ? std::max(1, settings.refinements + 1) : 1;
  // Cores of revolution with nearly parallel axes: the meridian bracket,
  // merged with the polygons' one (it is what makes nearly coaxial deep
  // pairs decidable: their depth is almost the same over a circle of
  // directions, and inscribed polygons converge only as the square of
  // their angular resolution).
  double meridian_lower = -std::numeric_limits<double>::infinity();
  double meridian_upper = std::numeric_limits<double>::infinity();
  // Overlapping pairs of revolution whose meridian bracket is wider than
  // the target (tilted beyond it): cutting planes on the difference's own
  // support points, merged the same way. It fails at once (one qhull of
  // 1 028 points) on separated pairs, which the polygons resolve.
  SupportHull cutting;
  const double target = settings.target_width * size;
  double azimuth_lower = 0.0, azimuth_upper = 0.0;
  const bool azimuth =
      curved && azimuth_bracket(core_a, core_b, target, settings.max_azimuth_evaluations, azimuth_lower, azimuth_upper);
  if (azimuth) {
    meridian_lower = azimuth_lower - radius;
    meridian_upper = azimuth_upper - radius;
  }
  double parallel_lower = 0.0, parallel_upper = 0.0;
  if (curved && !(azimuth && meridian_upper - meridian_lower <= target) &&
      meridian_bracket(core_a, core_b, parallel_lower, parallel_upper)) {
    meridian_lower = std::max(meridian_lower, parallel_lower - radius);
    meridian_upper = std::min(meridian_upper, parallel_upper - radius);
    if (meridian_upper - meridian_lower > target) {
      cutting = support_hull_bracket(core_a, core_b, settings.target_width * size, settings.max_support_points);
      if (cutting.ok) {
        out.support_points = cutting.points;
        meridian_lower = std::max(meridian_lower, cutting.lower - radius);
        meridian_upper = std::min(meridian_upper, cutting.upper - radius);
      }
    }
  }
  for (int pass = 0; pass < passes; ++pass) {
    const CoreAnswer core = core_distance(core_a.points, core_b.points);
    if (!core.ok) return fail(core.reason);
    const double sd = core.sd - radius;
    if (sd < upper || pass == 0) {
      upper = sd;
      kept = core;
    }
    const Vec& n = core.normal;
    lower = std::max(lower, -(core_a.support_value(n) + core_b.support_value(-n)) - radius);
    // Polytopes: also along -v/|v|, v = point_a - point_b the closest point
    // of the difference (on slivers qhull's facet normal is the worse
    // direction). Curved pairs refine their bracket below instead.
    const Vec v = core.point_a - core.point_b;
    if (!curved && core.sd > 0.0 && v.norm() > 0.0) {
      const Vec m = -v.normalized();
      lower = std::max(lower, -(core_a.support_value(m) + core_b.support_value(-m)) - radius);
    }
    // The cutting planes have done what refinement can (they stop at the
    // target or at their point budget, on a ring the polygons resolve no
    // better): the first pass only gives the witnesses' fallback.
    if (!curved || cutting.ok) break;
    if (std::min(upper, meridian_upper) - std::max(lower, meridian_lower) <=
        std::max(core.tolerance + core.flattening, settings.target_width * size))
      break;
    if (core.points > settings.max_difference_points) break;  // the bracket stays as wide as it is
    // Refine: exact support points of the curved cores in n and on a 3x3
    // grid of directions around it (spacing delta).
    const Vec p = any_perpendicular(n), q = n.cross(p);
    for (int i = -1; i <= 1; ++i) {
      for (int j = -1; j <= 1; ++j) {
        const Vec dir = (n + delta * (i * p + j * q)).normalized();
        if (core_a.curved()) core_a.points.push_back(core_a.support_point(dir));
        if (core_b.curved()) core_b.points.push_back(core_b.support_point(-dir));
      }
    }
    // Shrink the grid fast while the normal stays inside it, slowly when it
    // moved farther (two nearly tied features: the normal alternates and
    // each needs the grid).
    delta /= std::acos(std::clamp(n.dot(previous_normal), -1.0, 1.0)) <= delta ? 4 : 2;
    previous_normal = n;
  }

  const double rounding = kept.tolerance + kept.flattening;
  if (curved) {
    // The cutting-plane hull's facet gives the normal and the witnesses
    // when its bound is the one kept.
    if (cutting.ok && cutting.upper - radius < upper && cutting.upper - radius <= meridian_upper) {
      kept.normal = cutting.normal;
      kept.point_a = cutting.point_a;
      kept.point_b = cutting.point_b;
    }
    lower = std::max(lower, meridian_lower);
    upper = std::min(upper, meridian_upper);
    lower = std::min(lower, upper);  // rounding may cross them
    out.distance = 0.5 * (lower + upper);
    out.error_bound = 0.5 * (upper - lower) + rounding;
  } else {
    // qhull's answer checked against the support values of the pair along
    // its own normal: -h_D(n) is a certified lower bound of the signed
    // distance, equal to the answer (to rounding) when qhull's facets are
    // right. They are not on needles of aspect ~1e9, where qhull's facet
    // planes carry rounding far above its precision estimate (a needle
    // 1.66e-6 from a segment came out 1.87e-6 +- 3e-11); the disagreement
    // then widens the bound instead of passing for exact.
    out.distance = upper;
    const double disagreement = std::abs(upper - lower);
    out.error_bound = rounding + (disagreement > rounding ? disagreement : 0.0);
  }
  out.lower = out.distance - out.error_bound;
  out.upper = out.distance + out.error_bound;
  out.normal = kept.normal;
  out.normal_unique = kept.unique && !curved;
  out.normal_spread = kept.spread;
  out.point_a = centre + kept.point_a + core_a.radius * kept.normal;
  out.point_b = centre + kept.point_b - core_b.radius * kept.normal;
  out.dimension = kept.dimension;
  out.difference_points = kept.points;
  out.tolerance = kept.tolerance;
  out.ok = std::isfinite(out.distance) && std::isfinite(out.error_bound) && out.normal.allFinite() &&
           out.point_a.allFinite() && out.point_b.allFinite();
  if (!out.ok) return fail("non-finite result (input out of range)");
  return out;
}

ExactResult exact_signed_distance(const std::vector<Vec>& a_points, const std::vector<Vec>& b_points) {
  if (a_points.empty() || b_points.empty()) return fail("an empty point set");
  if (!finite_points(a_points) || !finite_points(b_points)) return fail("a point is not finite");
  Vec mean_a = Vec::Zero(), mean_b = Vec::Zero();
  for (const Vec& p : a_points) mean_a += p;
  for (const Vec& p : b_points) mean_b += p;
  mean_a /= static_cast<double>(a_points.size());
  mean_b /= static_cast<double>(b_points.size());
  const Vec centre = mean_a + 0.5 * (mean_b - mean_a);
  std::vector<Vec> a, b;
  a.reserve(a_points.size());
  b.reserve(b_points.size());
  for (const Vec& p : a_points) a.push_back(p - centre);
  for (const Vec& p : b_points) b.push_back(p - centre);
  const CoreAnswer core = core_distance(a, b);
  if (!core.ok) return fail(core.reason);
  ExactResult out;
  out.ok = true;
  out.distance = core.sd;
  // The certified lower bound along the answer's normal and along -v/|v|,
  // as in the shapes' version above.
  auto lower_along = [&](const Vec& n) {
    double h_a = -std::numeric_limits<double>::infinity(), h_b = -std::numeric_limits<double>::infinity();
    for (const Vec& p : a) h_a = std::max(h_a, p.dot(n));
    for (const Vec& p : b) h_b = std::max(h_b, -p.dot(n));
    return -(h_a + h_b);
  };
  double lower = lower_along(core.normal);
  const Vec v = core.point_a - core.point_b;
  if (core.sd > 0.0 && v.norm() > 0.0) lower = std::max(lower, lower_along(-v.normalized()));
  const double rounding = core.tolerance + core.flattening, disagreement = std::abs(core.sd - lower);
  out.error_bound = rounding + (disagreement > rounding ? disagreement : 0.0);
  out.lower = out.distance - out.error_bound;
  out.upper = out.distance + out.error_bound;
  out.normal = core.normal;
  out.normal_unique = core.unique;
  out.normal_spread = core.spread;
  out.point_a = centre + core.point_a;
  out.point_b = centre + core.point_b;
  out.dimension = core.dimension;
  out.difference_points = core.points;
  out.tolerance = core.tolerance;
  return out;
}

}  // namespace hedra::reference
