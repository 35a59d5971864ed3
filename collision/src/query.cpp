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
#include <hedra/collision/revolution_polytope.hpp>
#include <hedra/collision/tilted_revolution.hpp>
#include <hedra/hull/assert.hpp>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>

#include "closed_form.hpp"
#include "query_detail.hpp"
#include "sat_depth.hpp"

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

// Witness points with point_b - point_a = distance * n exactly (up to the
// final rounding): the midpoint of the two witnesses, moved apart along n.
// GJK's barycentric witnesses and its projected v can disagree by rounding
// times the simplex's conditioning (1.3e-9 of the size on a long flat
// cone); each point moves by half of that, within the uncertainty of a
// witness on so flat a surface.
void make_consistent(Eigen::Vector3d& point_a, Eigen::Vector3d& point_b, double distance, const Eigen::Vector3d& n) {
  const Eigen::Vector3d mid = 0.5 * (point_a + point_b);
  point_a = mid - (0.5 * distance) * n;
  point_b = mid + (0.5 * distance) * n;
}

// The world answer from the cores' (A's core frame): consistent witnesses,
// the radii added along n, then A's core offset and pose.
template <class Result>
void place_in_world(Result& out, const Eigen::Vector3d& offset_a, const Pose& pose_a, double radius_a, double radius_b,
                    Eigen::Vector3d core_a, Eigen::Vector3d core_b, double core_distance, const Eigen::Vector3d& n) {
  make_consistent(core_a, core_b, core_distance, n);
  const Eigen::Vector3d local_a = core_a + radius_a * n;
  const Eigen::Vector3d local_b = core_b - radius_b * n;
  out.normal = pose_a.rotation * n;
  out.point_a = pose_a.rotation * (offset_a + local_a) + pose_a.translation;
  out.point_b = pose_a.rotation * (offset_a + local_b) + pose_a.translation;
}

// pair_in_range() without its second look at the radii when they settle
// it (a pair with a shape of at least min_pair_extent is in range).
bool inputs_valid(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b) {
  double radius_a = 0.0, radius_b = 0.0;
  return pose_a.valid() && pose_b.valid() && is_valid(a, radius_a) && is_valid(b, radius_b) &&
         (std::max(radius_a, radius_b) >= min_pair_extent || pair_in_range(a, pose_a, b, pose_b));
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

  void store(GjkCache* cache, const GjkResult& g) const { store_cache(cache, g.v, core_a, core_b); }
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
  place_in_world(out, core_offset(a), pose_a, p.radius_a, p.radius_b, g.point_a, g.point_b, g.distance, n);
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

// ---- penetration(): a chain of named steps and one rule --------------------
//
// GJK runs first. Cores it certifies apart beyond the touching band answer
// with GJK (gjk_answer). Otherwise a signed step answers, the first that
// applies: exact_parallel_revolution, nearly_coaxial_branch_and_bound, epa
// (and, when EPA fails on overlapping cores, bracket_when_epa_fails, then
// polytope_and_revolution_when_epa_fails). The
// rule (choose) then keeps GJK's own bracket where EPA stalled on a narrower
// one (gjk_bracket_when_epa_stalls), the signed answer where the cores may
// overlap or where it is certified better and agrees with GJK, GJK's answer
// otherwise. Why each step is there: docs/design.md, "Why penetration()
// tries what it tries".

// One step's answer for the cores' signed distance, A's core frame: the
// true signed distance lies in [distance - error_bound, distance +
// error_bound] (exact arithmetic).
struct SignedAnswer {
  Status status = Status::ok;
  double distance = 0.0;  // > 0 apart, < 0 minus the depth
  double error_bound = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, from A toward B
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();
  int iterations = 0;     // EPA's iterations or the branch and bound's squares
  int support_calls = 0;  // beyond GJK's
};

SignedAnswer signed_answer_of(const EpaResult& e) {
  SignedAnswer s;
  s.status = to_status(e.status);
  s.distance = -e.depth;
  s.error_bound = e.error_bound;
  s.normal = e.normal;
  s.point_a = e.point_a;
  s.point_b = e.point_b;
  s.iterations = e.iterations;
  s.support_calls = e.support_calls;
  return s;
}

// The steps of penetration() on one pair, after GJK (`g`).
template <class Setup, class PlacedB>
class PenetrationSteps {
 public:
  PenetrationSteps(const Setup& p, const PlacedB& placed_b, const GjkResult& g, const PenetrationSettings& settings)
      : p_(p), placed_b_(placed_b), g_(g), settings_(settings) {}

  // The rule: the cores' answer; the signed step's counts go into `out`.
  SignedAnswer choose(PenetrationResult& out) {
    const double band = settings_.touching_band * p_.scale;
    // GJK's distance is unsigned: with a certified lower bound of 0 the
    // cores may be deep inside each other, and only a signed answer counts.
    const bool overlap_possible = g_.intersecting || !(g_.lower_bound > 0.0);
    if (!overlap_possible && !(g_.lower_bound <= band)) return gjk_answer();
    const SignedAnswer e = signed_answer(overlap_possible);
    out.epa_iterations = e.iterations;
    out.support_calls += e.support_calls;
    if (const std::optional<SignedAnswer> bracket = gjk_bracket_when_epa_stalls(e)) return *bracket;
    if (overlap_possible || signed_answer_better(e, band)) return e;
    return gjk_answer();
  }

 private:
  // Separated cores: GJK's answer (|v| > GJK's zero threshold > 0).
  SignedAnswer gjk_answer() const {
    SignedAnswer s;
    s.status = to_status(g_.status);
    s.distance = g_.distance;
    s.error_bound = g_.error_bound;
    s.normal = -g_.v / g_.distance;
    s.point_a = g_.point_a;
    s.point_b = g_.point_b;
    return s;
  }

  // Overlapping, touching or uncertain cores: the first signed step that
  // applies (the two exact paths for cores of revolution only where the
  // cores may overlap).
  SignedAnswer signed_answer(bool overlap_possible) {
    if (overlap_possible) {
      if (const std::optional<EpaResult> exact = exact_parallel_revolution()) return signed_answer_of(*exact);
      if (const std::optional<EpaResult> tilted = nearly_coaxial_branch_and_bound()) return signed_answer_of(*tilted);
    }
    EpaResult e = epa();
    if (overlap_possible && e.status != EpaStatus::ok && e.status != EpaStatus::degenerate)
      e = bracket_when_epa_fails(e);
    if (overlap_possible && e.status != EpaStatus::ok && e.status != EpaStatus::degenerate)
      e = polytope_and_revolution_when_epa_fails(e);
    return signed_answer_of(e);
  }

  // A polytope core and a curved core of revolution (a peg in a hole) that
  // EPA could not certify: the branch and bound over the azimuth
  // (revolution_polytope.hpp), hinted with EPA's normal; its answer when
  // certified or tighter than `e`.
  EpaResult polytope_and_revolution_when_epa_fails(const EpaResult& e) const {
    EpaResult q;
    if (!revolution_polytope_penetration(p_.core_a, p_.core_b, p_.relative, p_.scale, &e.normal, 1, settings_.epa, q))
      return e;
    return q.status == EpaStatus::ok || q.error_bound < e.error_bound ? q : e;
  }

  // Cores of revolution with parallel axes: the exact meridian-section
  // answer (revolution.hpp).
  std::optional<EpaResult> exact_parallel_revolution() const {
    EpaResult e;
    if (revolution_penetration(p_.core_a, p_.core_b, p_.relative, p_.scale, p_.relative.translation, settings_.epa, e))
      return e;
    return std::nullopt;
  }

  // The pair with B's axis made parallel to A's, whatever the tilt: within
  // theta R_B of the true depth (revolution.hpp); null when the pair is not
  // of that kind. Computed at most once.
  const EpaResult* parallel_bracket() {
    if (!parallel_tried_) {
      parallel_tried_ = true;
      parallel_known_ = revolution_penetration(p_.core_a, p_.core_b, p_.relative, p_.scale, p_.relative.translation,
                                               settings_.epa, parallel_, RevolutionTilt::any);
    }
    return parallel_known_ ? &parallel_ : nullptr;
  }

  // Cores of revolution with axes within kCoaxialTilt: the certified branch
  // and bound (tilted_revolution.hpp) with its first budget, when it
  // converges.
  std::optional<EpaResult> nearly_coaxial_branch_and_bound() {
    if (!nearly_coaxial(p_.core_a, p_.core_b, p_.relative)) return std::nullopt;
    const EpaResult* parallel = parallel_bracket();
    const Eigen::Vector3d hints[2] = {parallel ? parallel->normal : Eigen::Vector3d(-g_.v), p_.relative.translation};
    EpaResult q;
    TiltedRevolutionSettings first;
    first.max_squares = kCoaxialFirstSquares;
    if (tilted_revolution_penetration(p_.core_a, p_.core_b, p_.relative, p_.scale, hints, 2, settings_.epa, q, first) &&
        q.status == EpaStatus::ok)
      return q;
    return std::nullopt;
  }

  // EPA on the cores from GJK's final simplex (epa.hpp).
  EpaResult epa() const {
    return epa_penetration(p_.core_a, placed_b_, g_.simplex, p_.scale, p_.relative.translation, settings_.epa);
  }

  // EPA did not converge on overlapping cores: for cores of revolution, the
  // larger of the certified lower bounds and the smallest certified upper
  // bound that comes with a normal, from EPA, the parallel pair's normal
  // (h_D there) and the branch and bound with its full budget; `e`
  // unchanged for other cores.
  EpaResult bracket_when_epa_fails(EpaResult e) {
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
    const EpaResult* parallel = parallel_bracket();
    const EpaResult r = parallel ? *parallel : EpaResult{};
    bool bracketed = false;
    if (parallel) {
      const Eigen::Vector3d sa = p_.core_a.support(r.normal), sb = placed_b_.support(-r.normal);
      lower = std::max(lower, r.depth - r.error_bound);
      take_upper(r.normal.dot(sa - sb), r.normal, sa, sb);
      bracketed = true;
    }
    const Eigen::Vector3d hints[2] = {e.normal, r.normal};
    EpaResult q;
    if (tilted_revolution_penetration(p_.core_a, p_.core_b, p_.relative, p_.scale, hints, bracketed ? 2 : 1,
                                      settings_.epa, q)) {
      lower = std::max(lower, q.depth - q.error_bound);
      take_upper(q.depth, q.normal, q.point_a, q.point_b);
      bracketed = true;
    }
    if (bracketed) {
      e.error_bound = std::max(e.depth - lower, 0.0);
      const double tolerance =
          std::max(settings_.epa.relative_tolerance * e.depth, settings_.epa.absolute_tolerance * p_.scale);
      if (e.error_bound <= tolerance) e.status = EpaStatus::ok;
    }
    return e;
  }

  // EPA stalled, and GJK's own bracket of the signed distance, [signed
  // lower bound, |v|], is narrower than EPA's error bound: the upper end
  // |v| with normal -v/|v|, ok when the bracket is within GJK's tolerance,
  // stalled otherwise. (A cap or a full polytope keeps its own status.)
  std::optional<SignedAnswer> gjk_bracket_when_epa_stalls(const SignedAnswer& e) const {
    const double vn = g_.v.norm();
    const double gjk_gap = vn - g_.signed_lower_bound;
    if (!(e.status == Status::stalled && g_.status == GjkStatus::ok && vn > 0.0 && gjk_gap < e.error_bound))
      return std::nullopt;
    const double tolerance =
        std::max(settings_.gjk.relative_tolerance * vn, settings_.gjk.absolute_tolerance * p_.scale);
    SignedAnswer s;
    s.status = gjk_gap <= tolerance ? Status::ok : Status::stalled;
    s.distance = vn;
    s.error_bound = gjk_gap;
    s.normal = -g_.v / vn;
    s.point_a = g_.point_a;
    s.point_b = g_.point_b;
    return s;
  }

  // Cores GJK certifies apart, but not beyond the touching band: the signed
  // answer replaces GJK's when it converged, agrees with GJK's certified
  // separation (its interval does not lie below GJK's lower bound, beyond
  // rounding) and either |v| is within the band (GJK's normal is then
  // mostly rounding) or its certified error is smaller.
  bool signed_answer_better(const SignedAnswer& e, double band) const {
    const double rounding = 64.0 * std::numeric_limits<double>::epsilon() * p_.scale;
    const bool agrees = e.distance + e.error_bound >= g_.lower_bound - rounding;
    return e.status == Status::ok && agrees && (g_.distance <= band || e.error_bound <= g_.error_bound);
  }

  const Setup& p_;
  const PlacedB& placed_b_;
  const GjkResult& g_;
  const PenetrationSettings& settings_;
  bool parallel_tried_ = false;
  bool parallel_known_ = false;
  EpaResult parallel_;
};

// Two overlapping boxes: SAT's depth over the 15 axes, certified within
// EPA's tolerance (sat_depth.hpp), before GJK and EPA; false leaves the
// pair to them (apart, a zero extent, or the certificate fell short).
bool sat_depth_answer(const Box& a, const Pose& pose_a, const Box& b, const Pose& pose_b,
                      const PenetrationSettings& settings, PenetrationResult& out) {
  const RelativePose rel = relative_pose(pose_a, core_offset(a), pose_b, core_offset(b));
  const double radius_a = core_radius(a), radius_b = core_radius(b);
  const double scale = std::max(a.half_extents.norm() + radius_a, b.half_extents.norm() + radius_b);
  detail::SatDepth d;
  if (!detail::sat_depth(a, b, rel, scale, settings.epa, d)) return false;
  HEDRA_ASSERT(is_unit(d.normal) && d.error_bound >= 0.0 && d.distance <= 0.0);
  out.status = Status::ok;
  out.error_bound = d.error_bound;
  out.support_calls = d.axes_tested;
  out.distance = d.distance - (radius_a + radius_b);
  out.intersecting = out.distance <= 0.0;
  place_in_world(out, core_offset(a), pose_a, radius_a, radius_b, d.point_a, d.point_b, d.distance, d.normal);
  return true;
}

template <class SA, class SB>
PenetrationResult penetration_typed(const SA& a, const Pose& pose_a, const SB& b, const Pose& pose_b, GjkCache* cache,
                                    const PenetrationSettings& settings) {
  // A sphere whose centre is inside a box's core: the closed form
  // (closed_form.hpp), without GJK and EPA.
  if constexpr (std::is_same_v<SA, Sphere> && std::is_same_v<SB, Box>) {
    PenetrationResult out;
    if (closed_form::sphere_box(a, pose_a, b, pose_b, true, out)) return out;
  }
  if constexpr (std::is_same_v<SA, Box> && std::is_same_v<SB, Sphere>) {
    PenetrationResult out;
    if (closed_form::sphere_box(b, pose_b, a, pose_a, false, out)) return out;
  }
  if constexpr (std::is_same_v<SA, Box> && std::is_same_v<SB, Box>) {
    PenetrationResult out;
    if (sat_depth_answer(a, pose_a, b, pose_b, settings, out)) return out;
  }
  PairSetup<SA, SB> p(a, pose_a, b, pose_b, cache);
  const Transformed<decltype(p.core_b)> placed_b{p.core_b, p.relative.rotation, p.relative.translation};
  const GjkResult g = gjk_distance(p.core_a, placed_b, p.initial_axis, p.scale, settings.gjk);
  p.store(cache, g);

  PenetrationResult out;
  out.status = to_status(g.status);
  out.gjk_iterations = g.iterations;
  out.support_calls = g.support_calls;
  if (g.status == GjkStatus::degenerate) return out;
  PenetrationSteps<PairSetup<SA, SB>, decltype(placed_b)> steps(p, placed_b, g, settings);
  const SignedAnswer core = steps.choose(out);
  out.status = core.status;
  if (core.status == Status::degenerate) return out;
  HEDRA_ASSERT(is_unit(core.normal) && core.error_bound >= 0.0);
  out.error_bound = core.error_bound;
  out.distance = core.distance - (p.radius_a + p.radius_b);
  out.intersecting = out.distance <= 0.0;
  place_in_world(out, core_offset(a), pose_a, p.radius_a, p.radius_b, core.point_a, core.point_b, core.distance,
                 core.normal);
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
    out = Capsule{0.0, 0.5 * length, p->margin};
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

bool separated_beyond(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, double gap,
                      const GjkSettings& settings) {
  if (!(gap >= 0.0) || !inputs_valid(a, pose_a, b, pose_b)) return false;
  return detail::separated_beyond_unchecked(a, pose_a, b, pose_b, gap, settings);
}

bool detail::separated_beyond_unchecked(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                                        double gap, const GjkSettings& settings) {
  HEDRA_ASSERT(gap >= 0.0 && inputs_valid(a, pose_a, b, pose_b));
  return std::visit(
      [&](const auto& sa, const auto& sb) {
        using SA = std::decay_t<decltype(sa)>;
        using SB = std::decay_t<decltype(sb)>;
        PairSetup<SA, SB> p(sa, pose_a, sb, pose_b, nullptr);
        const Transformed<decltype(p.core_b)> placed_b{p.core_b, p.relative.rotation, p.relative.translation};
        const GjkResult g =
            gjk_intersect(p.core_a, placed_b, p.initial_axis, p.scale, p.radius_a + p.radius_b + gap, settings);
        return g.status == GjkStatus::ok && !g.intersecting;
      },
      a, b);
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
