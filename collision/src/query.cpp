// The type-erased queries: one std::visit over the pair of shapes, then typed
// GJK on the cores in A's core frame (see query.hpp and minkowski.hpp).
// Polyhedron support hints travel through the caller's GjkCache.
#include <algorithm>
#include <cmath>
#include <hedra/collision/epa.hpp>
#include <hedra/collision/gjk.hpp>
#include <hedra/collision/minkowski.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/revolution.hpp>
#include <hedra/collision/tilted_revolution.hpp>
#include <limits>
#include <utility>

namespace hedra::collision {

const char* to_string(Status status) {
  switch (status) {
    case Status::ok:
      return "ok";
    case Status::max_iterations:
      return "max_iterations";
    case Status::degenerate:
      return "degenerate";
    case Status::invalid_input:
      return "invalid_input";
    case Status::polytope_full:
      return "polytope_full";
    case Status::stalled:
      return "stalled";
  }
  return "unknown";
}

namespace {

Status to_status(GjkStatus s) {
  switch (s) {
    case GjkStatus::ok:
      return Status::ok;
    case GjkStatus::max_iterations:
      return Status::max_iterations;
    case GjkStatus::stalled:
      return Status::stalled;
    case GjkStatus::degenerate:
      return Status::degenerate;
  }
  return Status::degenerate;
}

template <class Core>
void load_hint(Core&, hull::Index) {}
void load_hint(PolyhedronCore& core, hull::Index hint) { core.hint = hint; }
template <class Core>
hull::Index hint_of(const Core&) {
  return 0;
}
hull::Index hint_of(const PolyhedronCore& core) { return core.hint; }

// Witness points with point_b - point_a = distance * n exactly (up to the
// final rounding): the midpoint of the two witnesses, moved apart along n.
// GJK's barycentric witnesses and its projected v can disagree by rounding
// times the simplex's conditioning (found by fuzzing: 8.7e-5 on a cone
// 6.6e4 long and 0.24 wide, 1.3e-9 of its size); each point moves by half of
// that, within the uncertainty of a witness on so flat a surface.
void make_consistent(Eigen::Vector3d& point_a, Eigen::Vector3d& point_b, double distance, const Eigen::Vector3d& n) {
  const Eigen::Vector3d mid = 0.5 * (point_a + point_b);
  point_a = mid - (0.5 * distance) * n;
  point_b = mid + (0.5 * distance) * n;
}

bool inputs_valid(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b) {
  return pose_a.valid() && pose_b.valid() && validate(a).ok() && validate(b).ok() &&
         pair_in_range(a, pose_a, b, pose_b);
}

// Everything a query needs, typed: both cores, B's core in A's core frame,
// the radii and the scale of the pair.
template <class SA, class SB>
struct PairSetup {
  decltype(core_of(std::declval<const SA&>())) core_a;
  decltype(core_of(std::declval<const SB&>())) core_b;
  RelativePose relative;
  double radius_a;
  double radius_b;
  double scale;
  Eigen::Vector3d initial_axis;

  PairSetup(const SA& a, const Pose& pose_a, const SB& b, const Pose& pose_b, const GjkCache* cache)
      : core_a(core_of(a)),
        core_b(core_of(b)),
        relative(relative_pose(pose_a, core_offset(a), pose_b, core_offset(b))),
        radius_a(core_radius(a)),
        radius_b(core_radius(b)) {
    scale = std::max(core_a.bounding_radius() + radius_a, core_b.bounding_radius() + radius_b);
    // The centre difference (A - B contains core_a's origin minus core_b's).
    initial_axis = -relative.translation;
    if (cache && cache->valid) {
      initial_axis = cache->axis;
      load_hint(core_a, cache->hint_a);
      load_hint(core_b, cache->hint_b);
    }
  }

  void store(GjkCache* cache, const GjkResult& g) const {
    if (!cache) return;
    if (g.v.allFinite() && g.v.squaredNorm() > 0.0) {
      cache->axis = g.v;
      cache->valid = true;
    }
    cache->hint_a = hint_of(core_a);
    cache->hint_b = hint_of(core_b);
  }
};

template <class SA, class SB>
IntersectResult intersect_typed(const SA& a, const Pose& pose_a, const SB& b, const Pose& pose_b, GjkCache* cache,
                                const GjkSettings& settings) {
  PairSetup<SA, SB> p(a, pose_a, b, pose_b, cache);
  const Transformed<decltype(p.core_b)> placed_b{p.core_b, p.relative.rotation, p.relative.translation};
  const GjkResult g = gjk_intersect(p.core_a, placed_b, p.initial_axis, p.scale, p.radius_a + p.radius_b, settings);
  p.store(cache, g);
  IntersectResult out;
  out.status = to_status(g.status);
  out.intersecting = g.status == GjkStatus::ok && g.intersecting;
  out.iterations = g.iterations;
  out.support_calls = g.support_calls;
  return out;
}

template <class SA, class SB>
DistanceResult distance_typed(const SA& a, const Pose& pose_a, const SB& b, const Pose& pose_b, GjkCache* cache,
                              const GjkSettings& settings) {
  PairSetup<SA, SB> p(a, pose_a, b, pose_b, cache);
  const Transformed<decltype(p.core_b)> placed_b{p.core_b, p.relative.rotation, p.relative.translation};
  const GjkResult g = gjk_distance(p.core_a, placed_b, p.initial_axis, p.scale, settings);
  p.store(cache, g);

  DistanceResult out;
  out.status = to_status(g.status);
  out.iterations = g.iterations;
  out.support_calls = g.support_calls;
  out.error_bound = g.error_bound;
  if (g.status == GjkStatus::degenerate) return out;
  const double radii = p.radius_a + p.radius_b;
  if (g.intersecting || g.distance <= radii) {
    out.intersecting = true;
    return out;
  }
  out.distance = g.distance - radii;
  // n from A toward B in A's core frame; |v| > radii >= 0 so the division is safe.
  const Eigen::Vector3d n = -g.v / g.distance;
  Eigen::Vector3d core_a = g.point_a, core_b = g.point_b;
  make_consistent(core_a, core_b, g.distance, n);
  const Eigen::Vector3d local_a = core_a + p.radius_a * n;
  const Eigen::Vector3d local_b = core_b - p.radius_b * n;
  const Eigen::Vector3d offset_a = core_offset(a);
  out.normal = pose_a.rotation * n;
  out.point_a = pose_a.rotation * (offset_a + local_a) + pose_a.translation;
  out.point_b = pose_a.rotation * (offset_a + local_b) + pose_a.translation;
  return out;
}

Status to_status(EpaStatus s) {
  switch (s) {
    case EpaStatus::ok:
      return Status::ok;
    case EpaStatus::max_iterations:
      return Status::max_iterations;
    case EpaStatus::polytope_full:
      return Status::polytope_full;
    case EpaStatus::stalled:
      return Status::stalled;
    case EpaStatus::degenerate:
      return Status::degenerate;
  }
  return Status::degenerate;
}

template <class SA, class SB>
PenetrationResult penetration_typed(const SA& a, const Pose& pose_a, const SB& b, const Pose& pose_b, GjkCache* cache,
                                    const PenetrationSettings& settings) {
  PairSetup<SA, SB> p(a, pose_a, b, pose_b, cache);
  const Transformed<decltype(p.core_b)> placed_b{p.core_b, p.relative.rotation, p.relative.translation};
  const GjkResult g = gjk_distance(p.core_a, placed_b, p.initial_axis, p.scale, settings.gjk);
  p.store(cache, g);

  PenetrationResult out;
  out.status = to_status(g.status);
  out.gjk_iterations = g.iterations;
  out.support_calls = g.support_calls;
  if (g.status == GjkStatus::degenerate) return out;
  // The cores' signed distance, normal (A's core frame) and witnesses:
  // GJK's when the cores are clearly apart, EPA's when they overlap or touch.
  double core_distance = g.distance;
  Eigen::Vector3d n = Eigen::Vector3d::Zero(), core_a = g.point_a, core_b = g.point_b;
  bool answered = false;
  const double band = settings.touching_band * p.scale;
  // GJK's distance is unsigned: with a certified lower bound of 0 it only
  // says "within error_bound of touching or overlapping", and the shapes may
  // be deep inside each other (seen: nearly coaxial cylinders, GJK's
  // triangle through the origin, |v| = 1e-14, true depth 0.71). Then only
  // the signed answer (EPA's, or the exact one for cores of revolution)
  // counts, whatever its status, as for overlapping cores.
  const bool overlap_possible = g.intersecting || !(g.lower_bound > 0.0);
  if (overlap_possible || g.lower_bound <= band) {
    // Overlapping cores of revolution with parallel axes: the exact
    // meridian-section answer (revolution.hpp) where EPA's polytope could
    // not certify a depth that is the same over a circle of directions.
    EpaResult e;
    // Nearly coaxial cores of revolution (axes within kCoaxialTilt): the
    // certified branch and bound over directions (tilted_revolution.hpp)
    // first, EPA only when it hits its cap.
    const bool exact_parallel = overlap_possible && revolution_penetration(p.core_a, p.core_b, p.relative, p.scale,
                                                                           p.relative.translation, settings.epa, e);
    bool tilted_done = false;
    EpaResult parallel;
    bool parallel_known = false;
    if (overlap_possible && !exact_parallel && nearly_coaxial(p.core_a, p.core_b, p.relative)) {
      parallel_known = revolution_penetration(p.core_a, p.core_b, p.relative, p.scale, p.relative.translation,
                                              settings.epa, parallel, true);
      const Eigen::Vector3d hints[2] = {parallel_known ? parallel.normal : Eigen::Vector3d(-g.v),
                                        p.relative.translation};
      EpaResult q;
      TiltedRevolutionSettings first;
      first.max_squares = kCoaxialFirstSquares;
      if (tilted_revolution_penetration(p.core_a, p.core_b, p.relative, p.scale, hints, 2, settings.epa, q, first) &&
          q.status == EpaStatus::ok) {
        e = q;
        tilted_done = true;
      }
    }
    if (!exact_parallel && !tilted_done)
      e = epa_penetration(p.core_a, placed_b, g.simplex, p.scale, p.relative.translation, settings.epa);
    // EPA could not converge on two cores of revolution (nearly coaxial
    // cylinders and cones: the depth is almost the same over a circle of
    // directions, and the polytope fills up before its lower bound rises):
    // the exact answer of the pair with B's axis made parallel to A's,
    // within theta R_B of the true depth, brackets it as well. Combined:
    // the larger of the two certified lower bounds, and the smallest of
    // the certified upper bounds that come with a normal: EPA's depth (the
    // best support value it saw) and the support value h_D of the true pair
    // along the parallel answer's normal (every h_D(n) bounds the depth from
    // above; this one is within theta R_B of the parallel depth).
    // And the branch and bound's own bracket, with its full budget.
    if (overlap_possible && e.status != EpaStatus::ok && e.status != EpaStatus::degenerate) {
      EpaResult r = parallel;
      double lower = e.depth - e.error_bound;
      const auto take_upper = [&](double h, const Eigen::Vector3d& normal, const Eigen::Vector3d& pa,
                                  const Eigen::Vector3d& pb) {
        if (std::isfinite(h) && h < e.depth) {
          e.depth = h;
          e.normal = normal;
          e.point_a = pa;
          e.point_b = pb;
        }
      };
      bool bracketed = false;
      if (parallel_known || revolution_penetration(p.core_a, p.core_b, p.relative, p.scale, p.relative.translation,
                                                   settings.epa, r, true)) {
        const Eigen::Vector3d sa = p.core_a.support(r.normal), sb = placed_b.support(-r.normal);
        lower = std::max(lower, r.depth - r.error_bound);
        take_upper(r.normal.dot(sa - sb), r.normal, sa, sb);
        bracketed = true;
      }
      const Eigen::Vector3d hints[2] = {e.normal, r.normal};
      EpaResult q;
      if (tilted_revolution_penetration(p.core_a, p.core_b, p.relative, p.scale, hints, bracketed ? 2 : 1, settings.epa,
                                        q)) {
        lower = std::max(lower, q.depth - q.error_bound);
        take_upper(q.depth, q.normal, q.point_a, q.point_b);
        bracketed = true;
      }
      if (bracketed) {
        e.error_bound = std::max(e.depth - lower, 0.0);
        const double tolerance =
            std::max(settings.epa.relative_tolerance * e.depth, settings.epa.absolute_tolerance * p.scale);
        if (e.error_bound <= tolerance) e.status = EpaStatus::ok;
      }
    }
    out.epa_iterations = e.iterations;
    out.support_calls += e.support_calls;
    // Overlap possible: the signed answer, whatever its status. Touching
    // from outside (GJK certifies a separation, but not above the band),
    // GJK's answer is valid too: EPA's replaces it when it converged and
    // either GJK's normal is rounding noise (|v| within the band) or EPA's
    // certified error is smaller (GJK stalls on curved cores near contact).
    // And only when the two agree: GJK's lower bound, v . w / |v| with w an
    // exact support point, survives rounding to a few eps of the scale,
    // while EPA's planes on slivers do not (found by fuzzing: a needle of
    // aspect 1.3e9 1.66e-6 from a segment, GJK certifying >= 1.23e-6 and
    // EPA claiming an overlap of 7e-10 with a zero bound). An EPA answer
    // whose certified interval lies below GJK's certified separation is
    // rounding, not an answer.
    const double rounding = 64.0 * std::numeric_limits<double>::epsilon() * p.scale;
    const bool agrees = -e.depth + e.error_bound >= g.lower_bound - rounding;
    const bool epa_better =
        e.status == EpaStatus::ok && agrees && (g.distance <= band || e.error_bound <= g.error_bound);
    // EPA stalled (rounding), and GJK's own bracket of the signed distance,
    // [signed lower bound, |v|], is narrower than EPA's error bound: GJK's
    // answer is the better one, the upper end |v| with normal -v/|v| (found
    // on needles of aspect 1e9 a hair apart: GJK converged with |v| below
    // its tolerance, EPA's first polytope was a sliver and it stalled). It
    // is ok when the bracket is within GJK's tolerance; stalled, with the
    // bracket as its bound, otherwise. (A cap or a full polytope keeps its
    // own status: the caller asked for the cap, and a deep pair's bracket
    // is wide anyway.)
    const double vn = g.v.norm();
    const double gjk_gap = vn - g.signed_lower_bound;
    if (e.status == EpaStatus::stalled && g.status == GjkStatus::ok && vn > 0.0 && gjk_gap < e.error_bound) {
      const double tolerance =
          std::max(settings.gjk.relative_tolerance * vn, settings.gjk.absolute_tolerance * p.scale);
      out.status = gjk_gap <= tolerance ? Status::ok : Status::stalled;
      core_distance = vn;
      n = -g.v / vn;
      out.error_bound = gjk_gap;
      answered = true;
    } else if (overlap_possible || epa_better) {
      out.status = to_status(e.status);
      if (e.status == EpaStatus::degenerate) return out;
      core_distance = -e.depth;
      n = e.normal;
      core_a = e.point_a;
      core_b = e.point_b;
      out.error_bound = e.error_bound;
      answered = true;
    }
  }
  if (!answered) {
    // Separated cores: |v| > GJK's zero threshold > 0.
    n = -g.v / g.distance;
    out.error_bound = g.error_bound;
  }
  out.distance = core_distance - (p.radius_a + p.radius_b);
  out.intersecting = out.distance <= 0.0;
  make_consistent(core_a, core_b, core_distance, n);
  const Eigen::Vector3d local_a = core_a + p.radius_a * n;
  const Eigen::Vector3d local_b = core_b - p.radius_b * n;
  const Eigen::Vector3d offset_a = core_offset(a);
  out.normal = pose_a.rotation * n;
  out.point_a = pose_a.rotation * (offset_a + local_a) + pose_a.translation;
  out.point_b = pose_a.rotation * (offset_a + local_b) + pose_a.translation;
  return out;
}

// Point and segment hulls (dimension 0 and 1, with their margins) are a
// sphere and a capsule: penetration() gives them those shapes' exact paths
// (revolution.hpp, tilted_revolution.hpp). Through EPA, a point hull on a
// cylinder's axis, where the depth is the same over a circle of directions,
// ended polytope_full on 200 of 200 random pairs (bounds up to 9e-4 of the
// depth); a sphere there is exact. (A GjkCache shared with distance() on
// the same segment hull then holds axes in two frames: only the warm start
// suffers.)
bool as_sphere_or_capsule(const Shape& shape, const Pose& pose, Shape& out, Pose& out_pose) {
  const Polyhedron* p = std::get_if<Polyhedron>(&shape);
  if (p == nullptr || !p->hull) return false;
  const ConvexPolyhedron& h = *p->hull;
  if (h.dimension() == 0 && h.vertex_count() == 1) {
    out = Sphere{0.0, p->margin};
    out_pose = {pose.rotation, pose.apply(h.offset() + h.vertex(0))};
    return true;
  }
  if (h.dimension() == 1 && h.vertex_count() == 2) {
    const Eigen::Vector3d d = h.vertex(1) - h.vertex(0);
    const double length = d.norm();
    if (!(length > 0.0) || !std::isfinite(length)) return false;
    // A frame whose z axis is the segment: (e1, k x e1, k) is right-handed.
    const Eigen::Vector3d k = d / length;
    const Eigen::Vector3d e1 = k.unitOrthogonal();
    Eigen::Matrix3d frame;
    frame.col(0) = e1;
    frame.col(1) = k.cross(e1);
    frame.col(2) = k;
    out = Capsule{0.5 * length, 0.0, p->margin};
    out_pose = {pose.rotation * frame, pose.apply(h.offset() + 0.5 * (h.vertex(0) + h.vertex(1)))};
    return true;
  }
  return false;
}

}  // namespace

bool pair_in_range(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b) {
  const double radius = std::max(bounding_radius(a), bounding_radius(b));
  if (radius >= min_pair_extent) return true;
  const auto origin = [](const Shape& s, const Pose& pose) {
    return std::visit([&](const auto& shape) { return pose.apply(core_offset(shape)); }, s);
  };
  const double reach = (origin(b, pose_b) - origin(a, pose_a)).cwiseAbs().maxCoeff();
  return reach >= min_pair_extent || (reach == 0.0 && radius == 0.0);
}

IntersectResult intersect(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, GjkCache* cache,
                          const GjkSettings& settings) {
  if (!inputs_valid(a, pose_a, b, pose_b)) return {Status::invalid_input, false, 0};
  return std::visit(
      [&](const auto& sa, const auto& sb) { return intersect_typed(sa, pose_a, sb, pose_b, cache, settings); }, a, b);
}

DistanceResult distance(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, GjkCache* cache,
                        const GjkSettings& settings) {
  if (!inputs_valid(a, pose_a, b, pose_b)) {
    DistanceResult out;
    out.status = Status::invalid_input;
    return out;
  }
  return std::visit(
      [&](const auto& sa, const auto& sb) { return distance_typed(sa, pose_a, sb, pose_b, cache, settings); }, a, b);
}

PenetrationResult penetration(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, GjkCache* cache,
                              const PenetrationSettings& settings) {
  if (!inputs_valid(a, pose_a, b, pose_b)) {
    PenetrationResult out;
    out.status = Status::invalid_input;
    return out;
  }
  Shape sphere_a, sphere_b;  // a Sphere each: no allocation
  Pose at_a = pose_a, at_b = pose_b;
  const bool converted_a = as_sphere_or_capsule(a, pose_a, sphere_a, at_a);
  const bool converted_b = as_sphere_or_capsule(b, pose_b, sphere_b, at_b);
  return std::visit(
      [&](const auto& sa, const auto& sb) { return penetration_typed(sa, at_a, sb, at_b, cache, settings); },
      converted_a ? sphere_a : a, converted_b ? sphere_b : b);
}

}  // namespace hedra::collision
