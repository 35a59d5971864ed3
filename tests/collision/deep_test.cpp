// Coincident and deep penetration on every pair of shape types:
// {sphere, box, capsule, cylinder, cone, hull}, each also with a margin,
// placed coincident (same centre, several relative rotations, among them
// coaxial ones where the depth is the same over a whole circle of
// directions) and deep (overlap 30 to 90 % of the smaller size).
//
// References, all independent of GJK/EPA:
//   * the signed distance of the cores, from conv{a_i - b_j} built by qhull
//     (the smallest facet offset when the origin is inside, the distance to
//     the hull otherwise), minus both radii (rounding adds a ball to the
//     Minkowski difference, so it shifts the signed distance exactly);
//   * point and segment cores (spheres, capsules) against each other: the
//     Minkowski difference is flat, its depth 0, the closed-form point and
//     segment distances;
//   * cylinders and cones: between two polytopes, one inscribed (rim
//     polygons on the circle) and one circumscribed (tangent polygons), on
//     angles graded around the rim point the reported normal selects (the
//     bracket is valid whatever the normal; it is narrow only if the
//     normal is right), width asserted below 1e-10 of the size;
//   * coaxial solids of revolution with the origin on their common axis
//     (every radial direction equally deep, where graded polygons cannot
//     be narrow): the meridian section of the Minkowski difference is the
//     Minkowski sum of the sections, a polygon; extruded far along the third
//     axis it is a prism whose qhull depth is the exact depth.
// Every answer: status ok, finite, unit normal, point_b - point_a =
// distance * normal, each witness on its shape's supporting plane and inside
// the shape (within 1e-9 of the size). Depth within 1e-9 of the size; the
// normal within 1e-6 rad of the reference facet's where the reference's
// nearest facet is unique (polytope pairs). Fixed seeds.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <hedra/collision/query.hpp>
#include <qhull_reference.hpp>
#include <random>
#include <string>
#include <vector>

#include "collision_test_support.hpp"

namespace hedra::collision {
namespace {

using namespace hedra::collision::testing;

using Vec = Eigen::Vector3d;

double angle(const Vec& u, const Vec& v) { return std::atan2(u.cross(v).norm(), u.dot(v)); }

// ---- the shapes ---------------------------------------------------------------

std::vector<Shape> shapes(std::shared_ptr<const ConvexPolyhedron> hull) {
  // Sizes chosen so that no two candidate directions tie exactly.
  std::vector<Shape> out = {Sphere{0.5, 0.0},          Box{{0.5, 0.37, 0.23}, 0.0}, Capsule{0.27, 0.33, 0.0},
                            Cylinder{0.41, 0.53, 0.0}, Cone{0.47, 0.52, 0.0},       Polyhedron{hull, 0.0}};
  const std::size_t n = out.size();
  for (std::size_t i = 0; i < n; ++i) {
    Shape s = out[i];
    std::visit([](auto& x) { x.margin = 0.1; }, s);
    out.push_back(s);
  }
  return out;
}

const char* kind(const Shape& s) {
  static const char* names[] = {"sphere", "box", "capsule", "cylinder", "cone", "hull"};
  return names[s.index()];
}

double margin_of(const Shape& s) {
  return std::visit([](const auto& x) { return x.margin; }, s);
}

bool is_curved(const Shape& s) { return std::holds_alternative<Cylinder>(s) || std::holds_alternative<Cone>(s); }

// ---- core vertex sets (polytopes, or polygon brackets of curved cores) ---------

// Angles graded around `centre`: spacing 1e-5 there, each next step half the
// angle reached (see near_contact_test.cpp for the error argument), at most
// 0.4 rad: away from the contact the polygons stay within r 0.4^2 / 8 of the
// circle, so directions whose depth exceeds the minimum by more than that
// cannot take over the bracket.
std::vector<double> graded_angles(double centre) {
  std::vector<double> offsets = {0.0};
  for (double s = 0.0; s < M_PI;) {
    s = std::min(M_PI, s + std::clamp(0.5 * s, 1e-5, 0.4));
    offsets.push_back(s);
  }
  std::vector<double> angles;
  for (auto it = offsets.rbegin(); it != offsets.rend(); ++it)
    if (*it < M_PI) angles.push_back(centre - *it);
  for (std::size_t i = 1; i < offsets.size(); ++i) angles.push_back(centre + offsets[i]);
  return angles;
}

// The union of the graded angles around each centre, in [0, 2 pi), sorted,
// without duplicates: finer than each set alone everywhere.
std::vector<double> graded_angles(const std::vector<double>& centres) {
  std::vector<double> all;
  for (double c : centres)
    for (double x : graded_angles(c)) {
      double y = std::fmod(x, 2.0 * M_PI);
      if (y < 0.0) y += 2.0 * M_PI;
      all.push_back(y);
    }
  std::sort(all.begin(), all.end());
  std::vector<double> out;
  for (double x : all)
    if (out.empty() || x - out.back() > 1e-12) out.push_back(x);
  if (out.size() > 1 && out.front() + 2.0 * M_PI - out.back() <= 1e-12) out.pop_back();
  return out;
}

void rim(double r, double z, const std::vector<double>& centres, bool outer, std::vector<Vec>& out) {
  // The angles are distinct modulo 2 pi; the polygon closes from the last
  // one back to the first.
  const std::vector<double> a = graded_angles(centres);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double next = i + 1 < a.size() ? a[i + 1] : a[0] + 2.0 * M_PI;
    if (!outer) {
      out.emplace_back(r * std::cos(a[i]), r * std::sin(a[i]), z);
    } else {
      const double half = 0.5 * (next - a[i]), mid = 0.5 * (next + a[i]);
      const double ro = r / std::cos(half);
      out.emplace_back(ro * std::cos(mid), ro * std::sin(mid), z);
    }
  }
}

// The core's points in the world frame: exact for polytopes, an inscribed
// (outer = false) or circumscribed polygon graded around the rim points the
// world directions `toward` select, for cylinders and cones.
std::vector<Vec> core_points(const Shape& s, const Pose& pose, const std::vector<Vec>& toward, bool outer) {
  std::vector<Vec> local;
  std::vector<double> centre;
  for (const Vec& d : toward) {
    const Vec t = pose.rotation.transpose() * d;
    centre.push_back(std::atan2(t.y(), t.x()));
  }
  if (std::holds_alternative<Sphere>(s)) {
    local.push_back(Vec::Zero());
  } else if (const auto* b = std::get_if<Box>(&s)) {
    for (int i = 0; i < 8; ++i)
      local.emplace_back(i & 1 ? b->half_extents.x() : -b->half_extents.x(),
                         i & 2 ? b->half_extents.y() : -b->half_extents.y(),
                         i & 4 ? b->half_extents.z() : -b->half_extents.z());
  } else if (const auto* c = std::get_if<Capsule>(&s)) {
    local.emplace_back(0.0, 0.0, -c->half_length);
    local.emplace_back(0.0, 0.0, c->half_length);
  } else if (const auto* y = std::get_if<Cylinder>(&s)) {
    rim(y->radius, -y->half_length, centre, outer, local);
    rim(y->radius, y->half_length, centre, outer, local);
  } else if (const auto* k = std::get_if<Cone>(&s)) {
    rim(k->radius, -k->half_length, centre, outer, local);
    local.emplace_back(0.0, 0.0, k->half_length);
  } else {
    const auto& h = *std::get<Polyhedron>(s).hull;
    for (const Vec& v : h.vertices()) local.push_back(h.offset() + v);
  }
  return posed(local, pose);
}

// qhull's facets of conv{a_i - b_j}, each as a plane by Newell's method
// (robust on slivers: a flat face of many nearly collinear rim points
// triangulates into triangles whose plain cross-product normals are off by
// ~eps / sin(angle)) with the offset the largest over its vertices.
struct Facets {
  std::vector<std::pair<double, Vec>> planes;  // offset (max over its vertices), unit normal
  double nearest = INFINITY;                   // distance from the origin to the boundary
  bool ok = false;
};

Facets facets_of(const std::vector<Vec>& a, const std::vector<Vec>& b) {
  std::vector<Vec> diff;
  for (const Vec& p : a)
    for (const Vec& q : b) diff.push_back(p - q);
  const reference::QhullHull h = reference::qhull_hull(diff, "Qt");
  EXPECT_TRUE(h.ok) << a.size() << " x " << b.size() << " points: " << h.messages;
  Facets out;
  out.ok = h.ok;
  for (const auto& f : h.facets) {
    Vec n = Vec::Zero();
    for (std::size_t i = 0; i < f.size(); ++i) n += diff[f[i]].cross(diff[f[(i + 1) % f.size()]]);
    n.normalize();
    double offset = -INFINITY;
    for (int i : f) offset = std::max(offset, n.dot(diff[i]));
    out.planes.emplace_back(offset, n);
    for (std::size_t i = 1; i + 1 < f.size(); ++i)
      out.nearest = std::min(out.nearest, point_triangle_distance(Vec::Zero(), diff[f[0]], diff[f[i]], diff[f[i + 1]]));
  }
  return out;
}

// Signed distance from the origin to the boundary of conv{a_i - b_j}: minus
// the smallest facet offset when the origin is inside (qhull), the distance
// otherwise; flat differences (point and segment cores) by closed forms.
double signed_core_distance(const std::vector<Vec>& a, const std::vector<Vec>& b, Vec* normal = nullptr) {
  if (a.size() <= 2 && b.size() <= 2) return segment_distance(a[0], a.back(), b[0], b.back());
  const Facets f = facets_of(a, b);
  // depth = min over facets of the support value along the facet normal,
  // computed over all points: a degenerate triangle's bogus normal then only
  // gives a larger value. Facets in increasing order of their vertices'
  // offset (a lower bound of that support value), stopping once it passes
  // the best.
  std::vector<std::pair<double, Vec>> planes = f.planes;
  std::sort(planes.begin(), planes.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  double best = INFINITY;
  for (const auto& [offset, n] : planes) {
    if (!(offset < best)) break;
    if (!n.allFinite()) continue;
    double h = -INFINITY;
    for (const Vec& p : a) {
      const double hp = n.dot(p);
      for (const Vec& q : b) h = std::max(h, hp - n.dot(q));
    }
    if (h < best) {
      best = h;
      if (normal) *normal = n;
    }
  }
  return best > 0.0 ? -best : f.nearest;
}

// The nearest facet's normal of conv{a_i - b_j} (origin inside) and whether
// it is unique within `tie`.
bool unique_reference_normal(const std::vector<Vec>& a, const std::vector<Vec>& b, double tie, Vec& normal) {
  if (a.size() <= 2 && b.size() <= 2) return false;  // flat difference: depth 0
  const Facets f = facets_of(a, b);
  if (!f.ok) return false;
  double best = INFINITY;
  normal = Vec::UnitX();
  for (const auto& [d, n] : f.planes)
    if (d < best) {
      best = d;
      normal = n;
    }
  if (!(best > tie)) return false;
  for (const auto& [d, n] : f.planes)
    if (d <= best + tie && angle(n, normal) > 1e-9) return false;
  return true;
}

// ---- coaxial solids of revolution: the meridian-section prism ---------------

// Meridian section (both sides of the axis) of a core of revolution, in
// (radial, axial) coordinates of its own frame; empty if not one.
std::vector<Eigen::Vector2d> section(const Shape& s) {
  if (std::holds_alternative<Sphere>(s)) return {{0.0, 0.0}};
  if (const auto* c = std::get_if<Capsule>(&s)) return {{0.0, -c->half_length}, {0.0, c->half_length}};
  if (const auto* y = std::get_if<Cylinder>(&s))
    return {{y->radius, -y->half_length},
            {-y->radius, -y->half_length},
            {y->radius, y->half_length},
            {-y->radius, y->half_length}};
  if (const auto* k = std::get_if<Cone>(&s))
    return {{k->radius, -k->half_length}, {-k->radius, -k->half_length}, {0.0, k->half_length}};
  return {};
}

// Exact signed core distance of two coaxial cores of revolution whose common
// axis is the world z axis through the world origin's... (see the caller):
// A's axial coordinates shifted by za, B's by zb, B's axis direction flipped
// when `flip`; the query point (the origin of the difference) sits on the
// axis. The sections' Minkowski difference, extruded to +-100 in the third
// axis, is a prism whose qhull depth is the section's.
double coaxial_core_distance(const Shape& a, double za, const Shape& b, double zb, bool flip) {
  std::vector<Vec> pa, pb;
  for (const auto& p : section(a))
    for (double y : {-100.0, 100.0}) pa.emplace_back(p.x(), y, p.y() + za);
  for (const auto& p : section(b)) pb.emplace_back(p.x(), 0.0, (flip ? -p.y() : p.y()) + zb);
  return signed_core_distance(pa, pb);
}

// ---- witness membership ---------------------------------------------------------

// Distance from the world point x to the posed core (0 inside).
double core_point_distance(const Shape& s, const Pose& pose, const Vec& x) {
  const Vec p = pose.rotation.transpose() * (x - pose.translation);
  if (std::holds_alternative<Sphere>(s)) return p.norm();
  if (const auto* b = std::get_if<Box>(&s)) return (p - p.cwiseMax(-b->half_extents).cwiseMin(b->half_extents)).norm();
  if (const auto* c = std::get_if<Capsule>(&s))
    return (p - closest_on_segment(p, Vec(0, 0, -c->half_length), Vec(0, 0, c->half_length))).norm();
  // Solids of revolution: the section in p's meridian half-plane.
  const double rho = std::hypot(p.x(), p.y());
  if (const auto* y = std::get_if<Cylinder>(&s)) {
    const double dr = std::max(rho - y->radius, 0.0), dz = std::max(std::abs(p.z()) - y->half_length, 0.0);
    return std::hypot(dr, dz);
  }
  if (const auto* k = std::get_if<Cone>(&s)) {
    const Vec q(rho, 0.0, p.z());
    return point_triangle_distance(q, Vec(0, 0, k->half_length), Vec(0, 0, -k->half_length),
                                   Vec(k->radius, 0, -k->half_length));
  }
  const auto& h = *std::get<Polyhedron>(s).hull;
  std::vector<Vec> verts;
  for (const Vec& v : h.vertices()) verts.push_back(h.offset() + v);
  return reference_distance({p}, verts);
}

double core_radius_of(const Shape& s) {
  if (const auto* x = std::get_if<Sphere>(&s)) return x->radius + x->margin;
  if (const auto* x = std::get_if<Capsule>(&s)) return x->radius + x->margin;
  return margin_of(s);
}

// ---- the check ----------------------------------------------------------------------

struct Tally {
  int queries = 0, failures = 0, normals = 0, coaxial = 0;
  double worst_depth = 0.0, worst_angle = 0.0, worst_bracket = 0.0;
};

// `coaxial_exact`: the exact signed distance when known in closed form
// (NaN otherwise, then qhull or the polygon bracket decides).
// The cores' bracket (signed core distances) of one placement, shared by
// the four margin variants of a pair (same cores, same poses).
struct CoreBracket {
  bool known = false;
  double lower = 0.0, upper = 0.0;
};

void check(const Shape& a, const Pose& pa, const Shape& b, const Pose& pb, double coaxial_exact,
           const std::string& what, Tally& tally, CoreBracket& memo) {
  const double size = std::max(bounding_radius(a), bounding_radius(b));
  const double tol = 1e-9 * size;
  const PenetrationResult r = penetration(a, pa, b, pb);
  ++tally.queries;
  const int failures_before = ::testing::UnitTest::GetInstance()->current_test_info()->result()->total_part_count();
  EXPECT_EQ(r.status, Status::ok) << what << " " << to_string(r.status) << " bound " << r.error_bound;
  ASSERT_TRUE(std::isfinite(r.distance) && r.normal.allFinite() && r.point_a.allFinite() && r.point_b.allFinite())
      << what;
  EXPECT_NEAR(r.normal.norm(), 1.0, 1e-12) << what;
  EXPECT_LT((r.point_b - r.point_a - r.distance * r.normal).norm(), tol) << what;
  // Witnesses on the supporting planes and inside the shapes.
  EXPECT_NEAR(r.normal.dot(r.point_a), support_value(a, pa, r.normal), tol) << what;
  EXPECT_NEAR(-r.normal.dot(r.point_b), support_value(b, pb, -r.normal), tol) << what;
  EXPECT_LE(core_point_distance(a, pa, r.point_a), core_radius_of(a) + tol) << what;
  EXPECT_LE(core_point_distance(b, pb, r.point_b), core_radius_of(b) + tol) << what;
  EXPECT_LE(r.error_bound, tol) << what;
  // Moving B by -distance * normal brings the shapes to touching (the
  // normal is a direction of least depth, not just any with that depth).
  const Pose moved{pb.rotation, pb.translation - r.distance * r.normal};
  EXPECT_NEAR(penetration(a, pa, b, moved).distance, 0.0, tol) << what << " (moved to touching)";

  const double radii = core_radius_of(a) + core_radius_of(b);
  double lower, upper;
  if (std::isfinite(coaxial_exact)) {
    lower = upper = coaxial_exact - radii;
    ++tally.coaxial;
  } else {
    // Graded around the reported normal; where another direction of the
    // inscribed pair comes out nearer (a second local minimum within the
    // coarse polygons' error), refined around that direction too.
    if (!memo.known) {
      std::vector<Vec> toward = {r.normal};
      for (int round = 0; round < 4; ++round) {
        std::vector<Vec> back;
        for (const Vec& d : toward) back.push_back(-d);
        Vec inner_normal = r.normal;
        memo.lower = signed_core_distance(core_points(a, pa, toward, true), core_points(b, pb, back, true));
        memo.upper =
            signed_core_distance(core_points(a, pa, toward, false), core_points(b, pb, back, false), &inner_normal);
        if (memo.upper - memo.lower <= 1e-10 * size) break;
        toward.push_back(inner_normal);
      }
      memo.known = true;
    }
    lower = memo.lower - radii;
    upper = memo.upper - radii;
  }
  EXPECT_LE(upper - lower, 1e-10 * size) << what << " (reference bracket too wide)";
  tally.worst_bracket = std::max(tally.worst_bracket, upper - lower);
  EXPECT_GE(r.distance, lower - tol) << what;
  EXPECT_LE(r.distance, upper + tol) << what;
  tally.worst_depth = std::max({tally.worst_depth, lower - r.distance, r.distance - upper});
  if (!is_curved(a) && !is_curved(b) && std::isnan(coaxial_exact)) {
    Vec n = Vec::UnitX();
    // The core difference's nearest facet normal, where unique and the
    // cores overlap (the rounding then keeps it).
    if (unique_reference_normal(core_points(a, pa, {r.normal}, false), core_points(b, pb, {-r.normal}, false),
                                1e-7 * size, n)) {
      ++tally.normals;
      EXPECT_LT(angle(r.normal, n), 1e-6) << what;
      tally.worst_angle = std::max(tally.worst_angle, angle(r.normal, n));
    }
  }
  const int failures_after = ::testing::UnitTest::GetInstance()->current_test_info()->result()->total_part_count();
  if (failures_after != failures_before) ++tally.failures;
}

Eigen::Matrix3d rotation(const Vec& axis, double angle_rad) {
  return Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
}

// The axis of a core of revolution in the world frame (none: zero).
bool revolution(const Shape& s) {
  return std::holds_alternative<Sphere>(s) || std::holds_alternative<Capsule>(s) ||
         std::holds_alternative<Cylinder>(s) || std::holds_alternative<Cone>(s);
}

struct Fixture {
  std::mt19937_64 rng{301};
  std::vector<Shape> zoo;
  Fixture() { zoo = shapes(make_hull(random_points(rng, 16, {0.5, 0.4, 0.3}))); }
};

TEST(DeepPenetration, CoincidentCentresEveryPair) {
  Fixture f;
  Tally tally;
  std::mt19937_64 rng(302);
  std::normal_distribution<double> g(0.0, 1.0);
  const Vec centre(0.3, -0.2, 0.1);
  // Relative rotations: none, a twist about the common axis (coaxial), a
  // flip (coaxial, axis reversed), a quarter turn, two generic ones.
  const std::vector<Eigen::Matrix3d> turns = {Eigen::Matrix3d::Identity(),  rotation(Vec::UnitZ(), 0.7),
                                              rotation(Vec::UnitX(), M_PI), rotation(Vec::UnitX(), 0.5 * M_PI),
                                              rotation(Vec(1, 2, 3), 0.9),  rotation(Vec(-2, 1, 0.5), 2.3)};
  const Eigen::Matrix3d base = rotation(Vec(0.3, -1.0, 0.4), 0.8);
  const std::size_t kinds = f.zoo.size() / 2;  // each kind, then each with a margin
  for (std::size_t ka = 0; ka < kinds; ++ka)
    for (std::size_t kb = 0; kb < kinds; ++kb)
      for (std::size_t t = 0; t < turns.size(); ++t) {
        CoreBracket memo;
        for (int m = 0; m < 4; ++m) {
          const Shape& a = f.zoo[ka + (m & 1 ? kinds : 0)];
          const Shape& b = f.zoo[kb + (m & 2 ? kinds : 0)];
          const Pose pa{base, centre};
          const Pose pb{base * turns[t], centre};
          double exact = NAN;
          // Coaxial: no turn, a twist, a flip, or any turn of a ball's centre.
          const bool ball = std::holds_alternative<Sphere>(a) || std::holds_alternative<Sphere>(b);
          if ((t < 3 || ball) && revolution(a) && revolution(b) && (is_curved(a) || is_curved(b)))
            exact = coaxial_core_distance(a, 0.0, b, 0.0, t == 2);
          check(a, pa, b, pb, exact,
                std::string(kind(a)) + (margin_of(a) > 0 ? "+m" : "") + " vs " + kind(b) +
                    (margin_of(b) > 0 ? "+m" : "") + " turn " + std::to_string(t),
                tally, memo);
        }
      }
  std::printf(
      "coincident: %d queries (%d coaxial exact, %d unique normals), %d failing; worst depth %.3g, "
      "normal %.3g rad, bracket %.3g\n",
      tally.queries, tally.coaxial, tally.normals, tally.failures, tally.worst_depth, tally.worst_angle,
      tally.worst_bracket);
  EXPECT_EQ(tally.failures, 0);
}

TEST(DeepPenetration, DeepOverlapEveryPair) {
  Fixture f;
  Tally tally;
  std::mt19937_64 rng(303);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> frac(0.3, 0.9);
  const std::size_t kinds = f.zoo.size() / 2;
  for (std::size_t ka = 0; ka < kinds; ++ka)
    for (std::size_t kb = 0; kb < kinds; ++kb)
      for (int k = 0; k < 6; ++k) {
        // Placed by the shapes without margin; the margin variants sit at
        // the same poses (same cores, deeper overlap).
        const Shape& a0 = f.zoo[ka];
        const Shape& b0 = f.zoo[kb];
        const Pose pa{rotation(Vec(g(rng), g(rng), g(rng)), g(rng)), Vec(g(rng), g(rng), g(rng))};
        Eigen::Matrix3d rb = rotation(Vec(g(rng), g(rng), g(rng)), g(rng));
        const Vec d = random_unit(rng);
        // Along d: touching at h_A(d) + h_B(-d), moved in by a fraction of
        // the smaller shape's diameter.
        const double ha = support_value(a0, Pose{pa.rotation, Vec::Zero()}, d);
        const double hb = support_value(b0, Pose{rb, Vec::Zero()}, -d);
        const double smaller = 2.0 * std::min(bounding_radius(a0), bounding_radius(b0));
        double exact_core = NAN;
        Vec offset = (ha + hb - frac(rng) * smaller) * d;
        if (k == 5 && revolution(a0) && revolution(b0) && (is_curved(a0) || is_curved(b0))) {
          // Coaxial, B moved along the common axis only: every radial
          // direction equally deep again.
          rb = pa.rotation * rotation(Vec::UnitZ(), 0.4);
          const double along = 0.6 * frac(rng) * smaller;
          offset = pa.rotation * Vec(0.0, 0.0, along);
          exact_core = coaxial_core_distance(a0, 0.0, b0, along, false);
        }
        const Pose pb{rb, pa.translation + offset};
        CoreBracket memo;
        for (int m = 0; m < 4; ++m) {
          const Shape& a = f.zoo[ka + (m & 1 ? kinds : 0)];
          const Shape& b = f.zoo[kb + (m & 2 ? kinds : 0)];
          check(a, pa, b, pb, exact_core,
                std::string(kind(a)) + (margin_of(a) > 0 ? "+m" : "") + " vs " + kind(b) +
                    (margin_of(b) > 0 ? "+m" : "") + " case " + std::to_string(k),
                tally, memo);
        }
      }
  std::printf(
      "deep: %d queries (%d coaxial exact, %d unique normals), %d failing; worst depth %.3g, normal %.3g "
      "rad, bracket %.3g\n",
      tally.queries, tally.coaxial, tally.normals, tally.failures, tally.worst_depth, tally.worst_angle,
      tally.worst_bracket);
  EXPECT_EQ(tally.failures, 0);
}

}  // namespace
}  // namespace hedra::collision

namespace hedra::collision {
namespace {

// Nearly coaxial cylinders, one inside the other (true depth 0.71 up to the
// tilt's effect, at most tilt x 0.67): GJK's simplex can pass within 1e-14
// of the origin and certify only "distance within 1e-14 of 0", which once
// came out as a touching answer with status ok. Every tilt must give the
// deep answer: exact (status ok) while the reduction to the meridian plane
// applies, otherwise EPA's best with an error bound that covers the truth.
TEST(DeepPenetration, NearlyCoaxialCylindersNeverReportTouching) {
  const Cylinder a{0.41, 0.53, 0.0}, b{0.3, 0.6, 0.0};
  for (double tilt : {0.0, 1e-14, 1e-12, 1e-10, 1e-8, 1e-6, 1e-4, 1e-2}) {
    const Pose pb{Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitX()).toRotationMatrix(), Eigen::Vector3d(0, 0, 0.05)};
    const PenetrationResult r = penetration(a, Pose::identity(), b, pb);
    ASSERT_TRUE(std::isfinite(r.distance) && r.normal.allFinite()) << tilt;
    EXPECT_LT(r.distance, -0.7) << tilt;
    EXPECT_LE(std::abs(r.distance + 0.71), r.error_bound + 0.67 * tilt + 1e-12) << tilt;
    if (tilt <= 1e-12) {
      EXPECT_EQ(r.status, Status::ok) << tilt;
      EXPECT_NEAR(r.distance, -0.71, 1e-12) << tilt;
    }
    if (r.status == Status::ok) {
      EXPECT_LE(r.error_bound, 1e-9) << tilt;
    }
  }
}

}  // namespace
}  // namespace hedra::collision
