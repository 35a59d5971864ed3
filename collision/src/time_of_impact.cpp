// time_of_impact (see time_of_impact.hpp): conservative advancement on
// GJK's certified separation and a bound on the closing speed.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <hedra/collision/detail/gjk.hpp>
#include <hedra/collision/time_of_impact.hpp>
#include <limits>

#include "cast_common.hpp"

namespace hedra::collision {

namespace {

using Vec = Eigen::Vector3d;

// A body's motion relative to the pair's origin: R(t) = exp(t angle axis) R0,
// x(t) = start + t delta.
struct Motion {
  Eigen::Matrix3d start_rotation;
  Vec axis = Vec::UnitZ();
  double angle = 0.0;  // [0, pi]
  Vec start = Vec::Zero();
  Vec delta = Vec::Zero();

  Eigen::Matrix3d rotation_at(double t) const {
    if (angle == 0.0) return start_rotation;
    return Eigen::AngleAxisd(t * angle, axis).toRotationMatrix() * start_rotation;
  }
  Vec position_at(double t) const { return start + t * delta; }
  Vec angular_velocity() const { return angle * axis; }
};

// The shorter arc from start to end: the quaternion of R1 R0^T with w >= 0.
Motion motion_of(const Sweep& sweep, const Vec& origin) {
  Motion m;
  m.start_rotation = sweep.start.rotation;
  Eigen::Quaterniond q(Eigen::Matrix3d(sweep.end.rotation * sweep.start.rotation.transpose()));
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double s = q.vec().norm();
  if (s > 0.0) {
    m.angle = 2.0 * std::atan2(s, q.w());
    m.axis = q.vec() / s;
  }
  m.start = sweep.start.translation - origin;
  m.delta = sweep.end.translation - sweep.start.translation;
  return m;
}

// The largest distance of the shape from its origin, the rotation centre.
template <class S, class Core>
double rotation_radius(const S& shape, const Core& core) {
  return core_offset(shape).norm() + core.bounding_radius() + core_radius(shape);
}

template <class SA, class SB>
struct ToiPair {
  decltype(core_of(std::declval<const SA&>())) core_a;
  decltype(core_of(std::declval<const SB&>())) core_b;
  Vec offset_a, offset_b;
  double radius_a, radius_b;  // rounding of the cores
  double reach_a, reach_b;    // rotation radii
  double scale;
  Motion motion_a, motion_b;

  ToiPair(const SA& a, const Sweep& sweep_a, const SB& b, const Sweep& sweep_b)
      : core_a(core_of(a)),
        core_b(core_of(b)),
        offset_a(core_offset(a)),
        offset_b(core_offset(b)),
        radius_a(core_radius(a)),
        radius_b(core_radius(b)),
        reach_a(rotation_radius(a, core_a)),
        reach_b(rotation_radius(b, core_b)),
        scale(std::max(core_a.bounding_radius() + radius_a, core_b.bounding_radius() + radius_b)),
        motion_a(motion_of(sweep_a, sweep_a.start.translation)),
        motion_b(motion_of(sweep_b, sweep_a.start.translation)) {}

  // The bound c on how fast the separation along n (world, A toward B) can shrink.
  double closing_bound(const Vec& n) const {
    return -n.dot(motion_b.delta - motion_a.delta) + n.cross(motion_a.angular_velocity()).norm() * reach_a +
           n.cross(motion_b.angular_velocity()).norm() * reach_b;
  }
};

// One step's view of the pair at t: GJK on the cores in A's core frame.
struct StepState {
  GjkResult gjk;
  Eigen::Matrix3d rotation_a;
  Vec position_a;
  double upper = 0.0;       // distance <= upper (GJK's |v| minus the radii)
  double separation = 0.0;  // distance >= separation along n (certified)
  Vec n = Vec::Zero();      // A toward B, A's core frame; zero if GJK gave no direction
};

template <class SA, class SB>
StepState evaluate(ToiPair<SA, SB>& p, double t, const Vec& axis, const GjkSettings& settings) {
  StepState s;
  s.rotation_a = p.motion_a.rotation_at(t);
  s.position_a = p.motion_a.position_at(t);
  const Pose pose_a{s.rotation_a, s.position_a};
  const Pose pose_b{p.motion_b.rotation_at(t), p.motion_b.position_at(t)};
  const RelativePose rel = relative_pose(pose_a, p.offset_a, pose_b, p.offset_b);
  const Transformed<decltype(p.core_b)> placed_b{p.core_b, rel.rotation, rel.translation};
  s.gjk = gjk_distance(p.core_a, placed_b, axis.squaredNorm() > 0.0 ? axis : Vec(-rel.translation), p.scale, settings);
  const double radii = p.radius_a + p.radius_b;
  s.upper = (s.gjk.intersecting ? 0.0 : s.gjk.distance) - radii;
  s.separation = -std::numeric_limits<double>::infinity();
  if (!s.gjk.intersecting && s.gjk.distance > 0.0) {
    s.n = -s.gjk.v / s.gjk.distance;
    // min over B of n . y minus max over A of n . x: every point pair is at
    // least this far apart along n.
    s.separation = s.n.dot(placed_b.support(-s.n) - p.core_a.support(s.n)) - radii;
  }
  return s;
}

template <class SA, class SB>
CastResult toi_typed(const SA& a, const Sweep& sweep_a, const SB& b, const Sweep& sweep_b, const Shape& shape_a,
                     const Shape& shape_b, const ToiSettings& settings, GjkCache* cache) {
  ToiPair<SA, SB> p(a, sweep_a, b, sweep_b);
  const double target = settings.target_distance + settings.linear_slop;
  const double reach = (p.motion_b.start).norm() + p.motion_a.delta.norm() + p.motion_b.delta.norm();
  const double rounding = 32.0 * std::numeric_limits<double>::epsilon() * (p.scale + reach);
  const double tolerance = std::max(settings.tolerance * p.scale, rounding);
  Vec axis = Vec::Zero();
  if (cache && cache->valid) {
    axis = cache->axis;
    load_hint(p.core_a, cache->hint_a);
    load_hint(p.core_b, cache->hint_b);
  }
  CastResult out;
  out.status = CastStatus::max_iterations;
  Vec last_n = Vec::Zero();
  double t = 0.0;
  while (out.iterations < settings.max_iterations) {
    ++out.iterations;
    const StepState s = evaluate(p, t, axis, settings.gjk);
    out.support_calls += s.gjk.support_calls + 1;
    if (s.gjk.status == GjkStatus::degenerate) {
      out.status = CastStatus::degenerate;
      break;
    }
    if (s.gjk.v.allFinite() && s.gjk.v.squaredNorm() > 0.0) axis = s.gjk.v;
    if (s.n.squaredNorm() > 0.0) last_n = s.n;
    if (s.upper <= target + tolerance) {
      if (t == 0.0) {
        store_cache(cache, axis, p.core_a, p.core_b);
        return cast_detail::initially_overlapping(shape_a, sweep_a.start, shape_b, sweep_b.start);
      }
      cast_detail::set_hit(out, t, s.upper + p.radius_a + p.radius_b, last_n, s.gjk.point_a, s.gjk.point_b, p.radius_a,
                           p.radius_b, target, s.rotation_a, s.position_a + sweep_a.start.translation, p.offset_a);
      break;
    }
    // Advance: the separation along n above the target over the closing bound.
    const double gap = s.separation - target;
    if (!(gap > 0.0)) {
      // GJK's bracket [separation, upper] straddles the target by more than
      // the tolerance: rounding (or GJK's cap) stopped it. At t = 0 nothing
      // has certified the start free yet: penetration() settles it.
      if (t == 0.0) {
        const cast_detail::Start start =
            cast_detail::settle_start(shape_a, sweep_a.start, shape_b, sweep_b.start, target, tolerance);
        if (start.within) {
          store_cache(cache, axis, p.core_a, p.core_b);
          return cast_detail::initially_overlapping(start.p);
        }
      }
      out.status = s.gjk.status == GjkStatus::max_iterations ? CastStatus::max_iterations : CastStatus::stalled;
      break;
    }
    const double closing = p.closing_bound(s.rotation_a * s.n);
    if (!(closing > 0.0) || t + gap / closing > 1.0) {
      out.status = CastStatus::separated;
      t = 1.0;
      break;
    }
    t += gap / closing;
  }
  store_cache(cache, axis, p.core_a, p.core_b);
  out.fraction = t;
  return out;
}

bool sweep_valid(const Sweep& s) { return s.start.valid() && s.end.valid(); }

}  // namespace

Pose pose_at(const Sweep& sweep, double t) {
  const Motion m = motion_of(sweep, Vec::Zero());
  return {m.rotation_at(t), m.position_at(t)};
}

CastResult time_of_impact(const Shape& a, const Sweep& sweep_a, const Shape& b, const Sweep& sweep_b, GjkCache* cache,
                          const ToiSettings& settings) {
  const bool valid = sweep_valid(sweep_a) && sweep_valid(sweep_b) && validate(a).ok() && validate(b).ok() &&
                     cast_detail::target_valid(settings.target_distance, settings.linear_slop) &&
                     pair_in_range(a, sweep_a.start, b, sweep_b.start);
  if (!valid) {
    CastResult out;
    out.status = CastStatus::invalid_input;
    return out;
  }
  return std::visit(
      [&](const auto& sa, const auto& sb) { return toi_typed(sa, sweep_a, sb, sweep_b, a, b, settings, cache); }, a, b);
}

}  // namespace hedra::collision
