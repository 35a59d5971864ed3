// Closed-form queries of a halfspace against every shape (halfspace.hpp).
//
// Everything runs in B's local frame: the halfspace's world normal n goes to
// u = R_b^T n, and a core point p of B (local) is g(p) = u . p + s0 - r above
// the surface, s0 = n . (t_b - t_a) - margin_a taken once (differences of
// translations first, so bodies far from the origin lose nothing of their
// size). The candidates are a fixed list per shape (at most ten; a
// polyhedron's vertices are read in place), so nothing is allocated.
// A kept point's depth is the gap on its line along n: g of its core point
// when the line leaves B there (a face at it faces down); otherwise the
// line's exit, in closed form for sharp boxes, hulls, cylinders and
// capsules, by one ray cast from below for rounded shapes and cones
// (raycast.hpp: capped, exact within 1e-10 of B's size).
//
// Invariants: the deepest candidate is B's exact support in -n (asserted in
// debug builds against support()); at most four points.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <hedra/collision/detail/support.hpp>
#include <hedra/collision/detail/vector_math.hpp>
#include <hedra/collision/halfspace.hpp>
#include <hedra/hull/assert.hpp>
#include <limits>
#include <variant>

namespace hedra::collision {

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kUnitTolerance = 1e-6;

// The pair, measured once.
struct Frame {
  Eigen::Vector3d n;            // world unit normal (A toward B)
  Eigen::Vector3d u;            // n in B's local frame
  double across = 0.0;          // |u_xy|: u's component across B's local z
  double s0 = 0.0;              // g(p) = u . p + s0 - rounding
  double rounding = 0.0;        // B's radius around its core
  double size = 0.0;            // B's bounding radius
  double rounding_error = 0.0;  // bound on the rounding of g
};

// Checks the input (invalid_input otherwise: is_valid() of both, valid
// poses, the pair's extent of query.hpp: B's size or its distance to the
// plane) and measures the pair once.
bool make_frame(const Halfspace& h, const Pose& pose_a, const Shape& b, const Pose& pose_b, Frame& f) {
  const double length = h.normal.norm();
  if (!(std::abs(length - 1.0) <= kUnitTolerance) || !(h.margin >= 0.0 && h.margin <= max_shape_size) ||
      !pose_a.valid() || !pose_b.valid() || !is_valid(b, f.size))
    return false;
  f.n = pose_a.rotation * (h.normal / length);
  f.n /= f.n.norm();
  f.u = pose_b.rotation.transpose() * f.n;
  f.across = std::sqrt(f.u.x() * f.u.x() + f.u.y() * f.u.y());
  const Eigen::Vector3d between = pose_b.translation - pose_a.translation;
  const double height = dot3(f.n, between);
  const double extent = std::max(f.size, std::abs(height));
  if (!(extent == 0.0 || extent >= min_pair_extent)) return false;
  f.s0 = height - h.margin;
  f.rounding = std::visit(
      [](const auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Sphere> || std::is_same_v<S, Capsule>) return s.radius + s.margin;
        return s.margin;
      },
      b);
  f.rounding_error = 16.0 * kEps * (between.cwiseAbs().sum() + f.size + h.margin);
  return true;
}

// Written before read (no initialisers: a list of ten is made per call).
struct Candidate {
  Eigen::Vector3d p;  // B's core point, local frame
  double g;           // its gap above the surface
  FeatureId id;
};

FeatureId feature(FeatureKind kind, std::uint32_t clip, std::uint32_t incident) {
  FeatureId id;
  id.kind = kind;
  id.reference = 0;
  id.clip = clip;
  id.incident = incident;
  return id;
}

// The candidates of every shape but a polyhedron (whose vertices are read in
// place), at most ten.
struct CandidateList {
  std::array<Candidate, 10> items;
  int count = 0;
  void add(const Frame& f, const Eigen::Vector3d& p, FeatureId id) {
    items[count++] = {p, dot3(f.u, p) + f.s0 - f.rounding, id};
  }
};

// A disc's rim at height z: the deepest rim point (along -u's projection;
// the +x point when u is along the axis) and the rim points on +x, -x, +y,
// -y that pass (g <= threshold). A rim point within `tie` of the deepest is
// that point: its id (stable), the deepest's position and gap (exact).
// `always`: the deepest is added even when it does not pass (it may be B's
// support).
void add_rim(const Frame& f, double radius, double z, std::uint32_t cap, double threshold, double tie, bool always,
             CandidateList& list) {
  const double w = f.across;
  const Eigen::Vector3d deep =
      w > 0.0 ? Eigen::Vector3d(-radius * (f.u.x() / w), -radius * (f.u.y() / w), z) : Eigen::Vector3d(radius, 0, z);
  const double g_deep = dot3(f.u, deep) + f.s0 - f.rounding;
  if (!always && !(g_deep <= threshold)) return;  // the rest of the rim lies higher
  const Eigen::Vector3d rim[4] = {{radius, 0.0, z}, {-radius, 0.0, z}, {0.0, radius, z}, {0.0, -radius, z}};
  bool merged = false;
  for (std::uint32_t k = 0; k < 4; ++k) {
    if (!merged && (rim[k] - deep).cwiseAbs().maxCoeff() <= tie) {
      list.items[list.count++] = {deep, g_deep, feature(FeatureKind::cap, cap, k)};
      merged = true;
      continue;
    }
    const double g = dot3(f.u, rim[k]) + f.s0 - f.rounding;
    if (g <= threshold) list.items[list.count++] = {rim[k], g, feature(FeatureKind::cap, cap, k)};
  }
  if (!merged) list.items[list.count++] = {deep, g_deep, feature(FeatureKind::cap, cap, 4)};
}

// A cylinder's two caps: the lower one always (it holds B's support), the
// other when its deepest rim point passes.
void add_caps(const Frame& f, double radius, double half_length, double threshold, double tie, CandidateList& list) {
  const bool top_lower = f.u.z() < 0.0;
  add_rim(f, radius, top_lower ? half_length : -half_length, top_lower ? 1 : 0, threshold, tie, true, list);
  add_rim(f, radius, top_lower ? -half_length : half_length, top_lower ? 0 : 1, threshold, tie, false, list);
}

struct ListCandidates {
  const CandidateList& list;
  int count() const { return list.count; }
  Candidate at(int i) const { return list.items[i]; }
  int find(const FeatureId& id) const {
    for (int i = 0; i < list.count; ++i)
      if (list.items[i].id == id) return i;
    return -1;
  }
};

// A polyhedron's vertices, read in place.
struct HullCandidates {
  const ConvexPolyhedron& hull;
  const Frame& f;
  double base;  // s0 + u . offset - rounding
  int count() const { return static_cast<int>(hull.vertex_count()); }
  Candidate at(int i) const {
    const Eigen::Vector3d& v = hull.vertex(static_cast<hull::Index>(i));
    return {v + hull.offset(), dot3(f.u, v) + base,
            feature(FeatureKind::face_vertex, hull::kInvalidIndex, static_cast<std::uint32_t>(i))};
  }
  int find(const FeatureId& id) const {
    return id.kind == FeatureKind::face_vertex && id.incident < hull.vertex_count() ? static_cast<int>(id.incident)
                                                                                    : -1;
  }
};

void build_list(const Frame& f, const Shape& b, double threshold, double tie, CandidateList& list) {
  if (std::holds_alternative<Sphere>(b)) {
    list.add(f, Eigen::Vector3d::Zero(), feature(FeatureKind::single, hull::kInvalidIndex, 0));
  } else if (const auto* box = std::get_if<Box>(&b)) {
    const Eigen::Vector3d& e = box->half_extents;
    for (std::uint32_t k = 0; k < 8; ++k)
      list.add(f, {(k & 1) ? e.x() : -e.x(), (k & 2) ? e.y() : -e.y(), (k & 4) ? e.z() : -e.z()},
               feature(FeatureKind::face_vertex, hull::kInvalidIndex, k));
  } else if (const auto* capsule = std::get_if<Capsule>(&b)) {
    list.add(f, {0.0, 0.0, -capsule->half_length}, feature(FeatureKind::segment, hull::kInvalidIndex, 0));
    list.add(f, {0.0, 0.0, capsule->half_length}, feature(FeatureKind::segment, hull::kInvalidIndex, 1));
  } else if (const auto* cylinder = std::get_if<Cylinder>(&b)) {
    add_caps(f, cylinder->radius, cylinder->half_length, threshold, tie, list);
  } else if (const auto* cone = std::get_if<Cone>(&b)) {
    list.add(f, {0.0, 0.0, cone->half_length}, feature(FeatureKind::cap, 1, 5));
    add_rim(f, cone->radius, -cone->half_length, 0, threshold, tie, true, list);
  }
}

// Candidates closer than `tie` to an earlier one are that one: the earlier
// id (stable), the deeper position (the depth stays exact).
void merge_coincident(CandidateList& list, double tie) {
  int kept = 0;
  for (int i = 0; i < list.count; ++i) {
    const Candidate c = list.items[i];
    int same = -1;
    for (int j = 0; j < kept && same < 0; ++j)
      if ((list.items[j].p - c.p).cwiseAbs().maxCoeff() <= tie) same = j;
    if (same < 0) {
      list.items[kept++] = c;
    } else if (c.g < list.items[same].g) {
      list.items[same].p = c.p;
      list.items[same].g = c.g;
    }
  }
  list.count = kept;
}

// The reduction of manifold.hpp's face contacts on the candidates with
// g <= threshold: the deepest (the first within `depth_tie` of the least
// gap), the farthest from it in the plane, the largest positive and
// negative signed areas with those two (first within the ties). Returns the
// number chosen into `chosen` and the candidates counted into `passing`.
template <class Candidates>
int reduce(const Candidates& c, const Eigen::Vector3d& u, double threshold, double depth_tie, double length_tie,
           std::array<int, kMaxContactPoints>& chosen, int& passing) {
  const int n = c.count();
  double least = std::numeric_limits<double>::infinity();
  passing = 0;
  for (int i = 0; i < n; ++i) {
    const double g = c.at(i).g;
    if (g <= threshold) ++passing;
    least = std::min(least, g);
  }
  if (passing == 0) return 0;
  int deepest = 0;
  while (c.at(deepest).g > least + depth_tie) ++deepest;
  if (passing <= kMaxContactPoints) {  // all of them, the deepest first
    int count = 0;
    chosen[count++] = deepest;
    for (int i = 0; i < n; ++i)
      if (i != deepest && c.at(i).g <= threshold) chosen[count++] = i;
    return count;
  }
  const Eigen::Vector3d pd = c.at(deepest).p;
  const auto planar = [&](const Eigen::Vector3d& d) { return Eigen::Vector3d(d - dot3(u, d) * u); };
  int count = 0;
  chosen[count++] = deepest;
  // The farthest from the deepest in the plane.
  double far2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const Candidate ci = c.at(i);
    if (ci.g <= threshold) far2 = std::max(far2, planar(ci.p - pd).squaredNorm());
  }
  const double far = std::sqrt(far2);
  if (!(far > length_tie)) return count;
  int farthest = -1;
  for (int i = 0; i < n && farthest < 0; ++i) {
    const Candidate ci = c.at(i);
    if (ci.g <= threshold && planar(ci.p - pd).norm() >= far - length_tie) farthest = i;
  }
  chosen[count++] = farthest;
  const Eigen::Vector3d edge = c.at(farthest).p - pd;
  const auto area = [&](const Eigen::Vector3d& p) { return dot3(u, cross3(edge, p - pd)); };
  double most = 0.0, least_area = 0.0;
  for (int i = 0; i < n; ++i) {
    const Candidate ci = c.at(i);
    if (ci.g > threshold) continue;
    const double a = area(ci.p);
    most = std::max(most, a);
    least_area = std::min(least_area, a);
  }
  const double area_tie = length_tie * far;
  if (most > area_tie) {
    for (int i = 0; i < n; ++i)
      if (c.at(i).g <= threshold && area(c.at(i).p) >= most - area_tie) {
        chosen[count++] = i;
        break;
      }
  }
  if (least_area < -area_tie) {
    for (int i = 0; i < n; ++i)
      if (c.at(i).g <= threshold && area(c.at(i).p) <= least_area + area_tie) {
        chosen[count++] = i;
        break;
      }
  }
  return count;
}

// The last answer's points, when all are still candidates and their deepest
// lies within `hold` of the least gap (manifold.hpp's ContactSettings::hold).
template <class Candidates>
int held(const Candidates& c, const ContactCache& cache, double threshold, double least, double hold,
         std::array<int, kMaxContactPoints>& chosen) {
  if (cache.kept_count <= 0 || cache.kept_count > kMaxContactPoints) return 0;
  double deepest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < cache.kept_count; ++k) {
    const int i = c.find(cache.kept[k]);
    if (i < 0 || c.at(i).g > threshold) return 0;
    chosen[k] = i;
    deepest = std::min(deepest, c.at(i).g);
  }
  return deepest <= least + hold ? cache.kept_count : 0;
}

#if HEDRA_ASSERTS_ENABLED
double least_gap(const Frame& f, const Shape& b) {
  // B's support in -u: the exact signed distance.
  const Eigen::Vector3d s = support(b, -f.u);  // rounding included
  return dot3(f.u, s) + f.s0;
}
#endif

// Does the line through candidate c's point along -n leave B right there
// (B's surface point on that line is c's)? A sharp feature: some face at it
// faces down (u . normal < 0). A rounded one never, but for B's support.
bool leaves_at(const Shape& b, const Frame& f, const Candidate& c) {
  if (f.rounding > 0.0) return false;
  const Eigen::Vector3d& u = f.u;
  if (std::holds_alternative<Box>(b)) {
    const std::uint32_t k = c.id.incident;
    return ((k & 1) ? u.x() : -u.x()) < 0.0 || ((k & 2) ? u.y() : -u.y()) < 0.0 || ((k & 4) ? u.z() : -u.z()) < 0.0;
  }
  if (const auto* poly = std::get_if<Polyhedron>(&b)) {
    const hull::HalfEdgeMesh& mesh = poly->hull->mesh();
    if (mesh.dimension() < 3) return true;  // no interior for the line to cross
    for (const hull::Index face : mesh.vertex_faces(c.id.incident))
      if (dot3(mesh.plane(face).normal, u) < 0.0) return true;
    return false;
  }
  const Eigen::Vector3d radial(c.p.x(), c.p.y(), 0.0);
  if (std::holds_alternative<Cylinder>(b)) return (c.p.z() > 0.0 ? u.z() : -u.z()) < 0.0 || dot3(radial, u) < 0.0;
  if (const auto* cone = std::get_if<Cone>(&b)) {
    if (c.id.incident == 5) {  // the apex: the line goes into the cone when -u lies in its angle
      const double down = u.z(), across = f.across;
      return !(down > 0.0 && 2.0 * cone->half_length * across <= cone->radius * down);
    }
    const Eigen::Vector3d slant = 2.0 * cone->half_length * radial + Eigen::Vector3d(0, 0, cone->radius * cone->radius);
    return u.z() > 0.0 || dot3(slant, u) < 0.0;
  }
  return true;  // a sphere's centre, a bare segment's ends
}

// The same for a capsule's end p (closed form): the line from p down, at
// p - t u, is within the radius r of the segment until t = r (the end's ball)
// when the segment runs up from p (a = the axis from p toward the other end,
// u . a >= 0), else until t = r / |u x a| (the side) while its foot stays on
// the segment, else to the other end's ball. Returned beyond the ball's r.
double capsule_drop(const Capsule& capsule, const Frame& f, const Candidate& c) {
  const double a_z = c.p.z() > 0.0 ? -1.0 : 1.0;  // a = (0, 0, a_z)
  const double along = -f.u.z() * a_z;            // (-u) . a: how fast the line runs along the axis
  if (!(along > 0.0)) return 0.0;
  const double r = f.rounding, length = 2.0 * capsule.half_length;
  const double across = f.across;  // |u x a|
  const double side = across > 0.0 ? r / across : std::numeric_limits<double>::infinity();
  if (side * along <= length) return side - r;
  // Past the other end: that ball, centre at distance `length` along a.
  // |t (-u) - length a|^2 = r^2, the larger root.
  const double t = length * along + std::sqrt(std::max(0.0, r * r - length * length * (1.0 - along * along)));
  return std::max(0.0, t - r);
}

// The same for a sharp box, hull or cylinder (closed forms): the line
// p - t u stays in the solid while every face plane it approaches (n_f . u
// < 0) is ahead, t <= (offset_f - n_f . p) / (-n_f . u) (p's own faces: 0,
// rounding clamped); the cylinder's side, a quadratic in t. Returns a
// negative value for the shapes it does not handle.
double sharp_drop(const Shape& b, const Frame& f, const Candidate& c) {
  if (f.rounding > 0.0) return -1.0;
  const Eigen::Vector3d& u = f.u;
  double t = std::numeric_limits<double>::infinity();
  const auto plane = [&](const Eigen::Vector3d& normal, double ahead) {
    const double approach = -dot3(normal, u);
    if (approach > 0.0) t = std::min(t, std::max(0.0, ahead) / approach);
  };
  if (const auto* box = std::get_if<Box>(&b)) {
    for (int i = 0; i < 3; ++i) {
      plane(Eigen::Vector3d::Unit(i), box->half_extents[i] - c.p[i]);
      plane(-Eigen::Vector3d::Unit(i), box->half_extents[i] + c.p[i]);
    }
  } else if (const auto* poly = std::get_if<Polyhedron>(&b)) {
    const hull::HalfEdgeMesh& mesh = poly->hull->mesh();
    const Eigen::Vector3d& v = poly->hull->vertex(c.id.incident);
    for (hull::Index face = 0; face < mesh.face_count(); ++face)
      plane(mesh.plane(face).normal, -mesh.plane(face).signed_distance(v));
  } else if (const auto* cylinder = std::get_if<Cylinder>(&b)) {
    plane(Eigen::Vector3d::UnitZ(), cylinder->half_length - c.p.z());
    plane(-Eigen::Vector3d::UnitZ(), cylinder->half_length + c.p.z());
    // |p_xy - t u_xy|^2 <= r^2: a t^2 - 2 b t + c0 <= 0, c0 <= 0 (p inside).
    const double a = u.x() * u.x() + u.y() * u.y();
    const double lin = c.p.x() * u.x() + c.p.y() * u.y();
    const double c0 = std::min(0.0, c.p.x() * c.p.x() + c.p.y() * c.p.y() - cylinder->radius * cylinder->radius);
    if (a > 0.0) t = std::min(t, std::max(0.0, (lin + std::sqrt(lin * lin - a * c0)) / a));
  } else {
    return -1.0;
  }
  return std::isfinite(t) ? t : 0.0;
}

// How far B's surface reaches below q (world) on the line along n: a ray
// from below B up that line (raycast.hpp: exact within 1e-10 of B's size).
double drop_below(const Shape& b, const Pose& pose_b, const Frame& f, const Eigen::Vector3d& q) {
  const double reach = 3.0 * f.size + std::abs(dot3(f.n, q - pose_b.translation));
  if (!(reach > 0.0)) return 0.0;
  const RaycastResult r = raycast(b, pose_b, q - reach * f.n, reach * f.n, 1.0);
  if (r.status != CastStatus::hit) return 0.0;
  return std::max(0.0, (1.0 - r.fraction) * reach);
}

template <class Candidates>
ContactResult contact_from(const Candidates& c, const Frame& f, const Shape& b, const Pose& pose_b, ContactCache* cache,
                           const ContactSettings& settings, ContactPath many_path) {
  ContactResult out;
  out.normal = f.n;
  const double threshold = settings.contact_distance + settings.penetration.touching_band * f.size;
  const double depth_tie = 4.0 * f.rounding_error;
  const double length_tie = 1e-6 * f.size;
  std::array<int, kMaxContactPoints> chosen{};
  int passing = 0;
  int count = reduce(c, f.u, threshold, depth_tie, length_tie, chosen, passing);
  out.stats.clipped_points = passing;
  double least = std::numeric_limits<double>::infinity();
  int deepest = -1;
  for (int i = 0; i < c.count(); ++i)
    if (c.at(i).g < least) least = c.at(i).g, deepest = i;
  HEDRA_ASSERT(deepest >= 0);
  out.distance = least;
  out.intersecting = least <= 0.0;
  // The deepest candidate is B's support in -n (the exact depth).
  HEDRA_ASSERT(std::abs(least - least_gap(f, b)) <= 4.0 * f.rounding_error + 1e-12 * f.size);
  const auto on_b = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d { return pose_b.apply(p) - f.rounding * f.n; };
  out.point_b = on_b(c.at(deepest).p);
  out.point_a = out.point_b - least * f.n;
  if (count == 0) {
    out.path = ContactPath::separated;
    if (cache) cache->kept_count = 0;
    return out;
  }
  if (cache && settings.hold > 0.0) {
    std::array<int, kMaxContactPoints> kept{};
    const int n_kept = held(c, *cache, threshold, least, settings.hold * f.size, kept);
    if (n_kept > 0) chosen = kept, count = n_kept;
  }
  out.count = count;
  bool one_cap = true;
  for (int k = 0; k < count; ++k) {
    const Candidate ck = c.at(chosen[k]);
    Eigen::Vector3d q = on_b(ck.p);
    double g = ck.g;
    // B's surface on the line along n through q: q itself for B's support
    // and features that face down, otherwise measured.
    if (chosen[k] != deepest && !leaves_at(b, f, ck)) {
      double drop =
          std::holds_alternative<Capsule>(b) ? capsule_drop(std::get<Capsule>(b), f, ck) : sharp_drop(b, f, ck);
      if (drop < 0.0) drop = drop_below(b, pose_b, f, q);  // rounded shapes, cones: a ray from below
      q -= drop * f.n;
      g -= drop;
    }
    out.points[k].point = q - (g / 2.0) * f.n;
    out.points[k].depth = -g;
    out.points[k].id = ck.id;
    one_cap = one_cap && ck.id.clip == c.at(chosen[0]).id.clip;
  }
  out.path = count == 1 ? ContactPath::single_point
                        : (many_path == ContactPath::cap && !one_cap ? ContactPath::segment : many_path);
  if (cache) {
    cache->kept_count = count;
    for (int k = 0; k < count; ++k) cache->kept[k] = out.points[k].id;
  }
  return out;
}

}  // namespace

ShapeValidation validate(const Halfspace& h) {
  char buffer[200];
  if (!h.normal.allFinite()) {
    std::snprintf(buffer, sizeof buffer, "halfspace normal = (%.17g, %.17g, %.17g) is not finite", h.normal.x(),
                  h.normal.y(), h.normal.z());
    return {ShapeError::non_finite, buffer};
  }
  if (!(std::abs(h.normal.norm() - 1.0) <= kUnitTolerance)) {
    std::snprintf(buffer, sizeof buffer, "halfspace normal = (%.17g, %.17g, %.17g) is not a unit vector (|n| = %.17g)",
                  h.normal.x(), h.normal.y(), h.normal.z(), h.normal.norm());
    return {ShapeError::out_of_range, buffer};
  }
  if (!std::isfinite(h.margin)) {
    std::snprintf(buffer, sizeof buffer, "halfspace margin = %.17g", h.margin);
    return {ShapeError::non_finite, buffer};
  }
  if (h.margin < 0.0) {
    std::snprintf(buffer, sizeof buffer, "halfspace margin = %.17g", h.margin);
    return {ShapeError::negative_margin, buffer};
  }
  if (h.margin > max_shape_size) {
    std::snprintf(buffer, sizeof buffer, "halfspace margin = %.17g is larger than max_shape_size (1e60)", h.margin);
    return {ShapeError::out_of_range, buffer};
  }
  return {};
}

bool is_valid(const Halfspace& h) {
  return h.normal.allFinite() && std::abs(h.normal.norm() - 1.0) <= kUnitTolerance && h.margin >= 0.0 &&
         h.margin <= max_shape_size;
}

PenetrationResult penetration(const Halfspace& a, const Pose& pose_a, const Shape& b, const Pose& pose_b) {
  PenetrationResult out;
  Frame f;
  if (!make_frame(a, pose_a, b, pose_b, f)) {
    out.status = Status::invalid_input;
    return out;
  }
  const Eigen::Vector3d s = support(b, -f.u);
  out.distance = dot3(f.u, s) + f.s0;
  out.intersecting = out.distance <= 0.0;
  out.normal = f.n;
  out.point_b = pose_b.apply(s);
  out.point_a = out.point_b - out.distance * f.n;
  out.error_bound = f.rounding_error;
  out.support_calls = 1;
  return out;
}

DistanceResult distance(const Halfspace& a, const Pose& pose_a, const Shape& b, const Pose& pose_b) {
  DistanceResult out;
  const PenetrationResult p = penetration(a, pose_a, b, pose_b);
  out.status = p.status;
  if (p.status != Status::ok) return out;
  out.support_calls = 1;
  out.error_bound = p.error_bound;
  out.intersecting = p.intersecting;
  if (p.intersecting) return out;
  out.distance = p.distance;
  out.normal = p.normal;
  out.point_a = p.point_a;
  out.point_b = p.point_b;
  return out;
}

IntersectResult intersect(const Halfspace& a, const Pose& pose_a, const Shape& b, const Pose& pose_b) {
  IntersectResult out;
  const PenetrationResult p = penetration(a, pose_a, b, pose_b);
  out.status = p.status;
  out.intersecting = p.status == Status::ok && p.intersecting;
  out.support_calls = p.support_calls;
  return out;
}

ContactResult contact(const Halfspace& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, ContactCache* cache,
                      const ContactSettings& settings) {
  Frame f;
  if (!make_frame(a, pose_a, b, pose_b, f) || !std::isfinite(settings.contact_distance)) {
    ContactResult out;
    out.status = Status::invalid_input;
    return out;
  }
  if (const auto* poly = std::get_if<Polyhedron>(&b)) {
    const ConvexPolyhedron& hull = *poly->hull;
    const HullCandidates c{hull, f, f.s0 + dot3(f.u, hull.offset()) - f.rounding};
    return contact_from(c, f, b, pose_b, cache, settings, ContactPath::face_a);
  }
  CandidateList list;
  const double tie = 1e-6 * f.size;
  build_list(f, b, settings.contact_distance + settings.penetration.touching_band * f.size, tie, list);
  // Points that coincide: a box with a zero extent, a rim of zero radius.
  const Box* box = std::get_if<Box>(&b);
  const bool thin = box ? !(box->half_extents.minCoeff() > tie)
                        : (std::holds_alternative<Cylinder>(b) && !(std::get<Cylinder>(b).radius > tie)) ||
                              (std::holds_alternative<Cone>(b) && !(std::get<Cone>(b).radius > tie));
  if (thin) merge_coincident(list, tie);
  const ContactPath path = std::holds_alternative<Box>(b)       ? ContactPath::face_a
                           : std::holds_alternative<Capsule>(b) ? ContactPath::segment
                           : std::holds_alternative<Sphere>(b)  ? ContactPath::single_point
                                                                : ContactPath::cap;
  return contact_from(ListCandidates{list}, f, b, pose_b, cache, settings, path);
}

RaycastResult raycast(const Halfspace& h, const Pose& pose, const Eigen::Vector3d& origin,
                      const Eigen::Vector3d& direction, double max_fraction, const RaycastSettings& settings) {
  (void)settings;
  RaycastResult out;
  if (!is_valid(h) || !pose.valid() || !origin.allFinite() || !direction.allFinite() ||
      !(max_fraction >= 0.0 && max_fraction <= max_coordinate) || origin.cwiseAbs().maxCoeff() > max_coordinate ||
      direction.cwiseAbs().maxCoeff() > max_coordinate) {
    out.status = CastStatus::invalid_input;
    return out;
  }
  Eigen::Vector3d n = pose.rotation * (h.normal / h.normal.norm());
  n /= n.norm();
  const Eigen::Vector3d from = origin - pose.translation;
  const double height = dot3(n, from) - h.margin;
  const double tolerance = 16.0 * kEps * (from.cwiseAbs().sum() + h.margin);
  out.error_bound = tolerance;
  if (height <= tolerance) {
    out.status = CastStatus::initially_overlapping;
    out.hit = out.started_inside = true;
    out.point = origin;
    return out;
  }
  const double descent = -dot3(n, direction);
  // Reaches the surface within max_fraction: height <= max_fraction * descent.
  if (!(descent > 0.0) || !(height <= max_fraction * descent)) {
    out.status = CastStatus::separated;
    out.fraction = max_fraction;
    return out;
  }
  out.status = CastStatus::hit;
  out.hit = true;
  out.fraction = std::min(height / descent, max_fraction);
  out.point = origin + out.fraction * direction;
  out.normal = n;
  return out;
}

}  // namespace hedra::collision
