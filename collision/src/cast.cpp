// shape_cast (see cast.hpp): a GJK ray cast along the relative translation
// against the cores' Minkowski difference, grown by the radii and the target.
#include <algorithm>
#include <cmath>
#include <hedra/collision/cast.hpp>
#include <hedra/collision/detail/gjk_raycast.hpp>
#include <limits>

#include "cast_common.hpp"

namespace hedra::collision {

namespace {

using Vec = Eigen::Vector3d;

template <class SA, class SB>
CastResult shape_cast_typed(const SA& a, const Pose& pose_a, const Vec& translation_a, const SB& b, const Pose& pose_b,
                            const Vec& translation_b, const Shape& shape_a, const Shape& shape_b,
                            const ShapeCastSettings& settings, GjkCache* cache) {
  auto core_a = core_of(a);
  auto core_b = core_of(b);
  const RelativePose relative = relative_pose(pose_a, core_offset(a), pose_b, core_offset(b));
  const Transformed<decltype(core_b)> placed_b{core_b, relative.rotation, relative.translation};
  const double radius_a = core_radius(a), radius_b = core_radius(b);
  const double target = settings.target_distance + settings.linear_slop;
  const double scale = std::max(core_a.bounding_radius() + radius_a, core_b.bounding_radius() + radius_b);
  const double rounding = 32.0 * std::numeric_limits<double>::epsilon() * (scale + relative.translation.norm());
  const double tolerance = std::max(settings.tolerance * scale, rounding);
  // B's motion relative to A, in A's core frame: the ray.
  const Vec u = pose_a.rotation.transpose() * (translation_b - translation_a);
  // v points from K toward the ray's point: B's side, about B's centre.
  Vec axis = relative.translation;
  if (cache && cache->valid) {
    axis = -cache->axis;
    load_hint(core_a, cache->hint_a);
    load_hint(core_b, cache->hint_b);
  }
  if (!(axis.squaredNorm() > 0.0)) axis = -u;
  const auto cast = [&](const Vec& from) {
    return gjk_raycast(core_a, placed_b, radius_a + radius_b + target, u, 1.0, from, tolerance,
                       settings.max_iterations);
  };
  GjkRaycastResult g = cast(axis);
  int iterations = g.iterations, support_calls = g.support_calls;
  if (start_unsettled(g)) {
    // A stall or the cap before the first clip certifies nothing at t = 0
    // (gjk_raycast.hpp): penetration() settles the start. Within the
    // target: that answer; apart: one more ray cast from its separating
    // direction (a stall there leaves t = 0, now known to be free).
    const cast_detail::Start start = cast_detail::settle_start(shape_a, pose_a, shape_b, pose_b, target, tolerance);
    if (start.within) {
      CastResult out = cast_detail::initially_overlapping(start.p);
      out.iterations = iterations;
      out.support_calls += support_calls;
      return out;
    }
    if (start.apart) {
      g = cast(pose_a.rotation.transpose() * start.p.normal);
      iterations += g.iterations;
      support_calls += start.p.support_calls + g.support_calls;
    }
  }
  store_cache(cache, -g.v, core_a, core_b);

  CastResult out;
  out.status = g.status;
  out.iterations = iterations;
  out.support_calls = support_calls;
  out.fraction = g.lambda;
  switch (g.status) {
    case CastStatus::hit: {
      const Vec core_b_at = g.point_b + g.lambda * u;  // B has moved by lambda u
      const Vec n = safe_unit(g.normal);
      cast_detail::set_hit(out, g.lambda, g.v.norm(), n, g.point_a, core_b_at, radius_a, radius_b, target,
                           pose_a.rotation, pose_a.translation + g.lambda * translation_a, core_offset(a));
      return out;
    }
    case CastStatus::initially_overlapping: {
      CastResult start = cast_detail::initially_overlapping(shape_a, pose_a, shape_b, pose_b);
      start.iterations = iterations;
      start.support_calls += support_calls;
      return start;
    }
    case CastStatus::separated:
      out.fraction = 1.0;
      return out;
    default:  // max_iterations, stalled: lambda is safe; degenerate
      return out;
  }
}

}  // namespace

CastResult shape_cast(const Shape& a, const Pose& pose_a, const Eigen::Vector3d& translation_a, const Shape& b,
                      const Pose& pose_b, const Eigen::Vector3d& translation_b, GjkCache* cache,
                      const ShapeCastSettings& settings) {
  const bool valid = pose_a.valid() && pose_b.valid() && validate(a).ok() && validate(b).ok() &&
                     cast_detail::finite_within(translation_a) && cast_detail::finite_within(translation_b) &&
                     cast_detail::target_valid(settings.target_distance, settings.linear_slop) &&
                     pair_in_range(a, pose_a, b, pose_b);
  if (!valid) {
    CastResult out;
    out.status = CastStatus::invalid_input;
    return out;
  }
  return std::visit(
      [&](const auto& sa, const auto& sb) {
        return shape_cast_typed(sa, pose_a, translation_a, sb, pose_b, translation_b, a, b, settings, cache);
      },
      a, b);
}

}  // namespace hedra::collision
