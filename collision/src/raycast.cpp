// Ray casts (see raycast.hpp): the ray in the core's frame, then a closed
// form (ball, capsule, box, cylinder) or the GJK ray cast (gjk_raycast.hpp).
#include <algorithm>
#include <cmath>
#include <hedra/collision/detail/gjk_raycast.hpp>
#include <hedra/collision/detail/minkowski.hpp>
#include <hedra/collision/raycast.hpp>
#include <limits>

#include "cast_common.hpp"

namespace hedra::collision {

namespace {

using Vec = Eigen::Vector3d;

// A hit in the core's frame.
struct LocalHit {
  CastStatus status = CastStatus::separated;
  double fraction = 0.0;
  Vec normal = Vec::Zero();
  double error_bound = 0.0;
  int iterations = 0;
};

LocalHit inside() { return {CastStatus::initially_overlapping, 0.0, Vec::Zero(), 0.0, 0}; }

// The ball of radius `r` around c; the ray o + t d starts outside it (beyond
// the tolerance). A ray passing within the tolerance of the ball touches it
// at its closest approach.
LocalHit ray_ball(const Vec& o, const Vec& d, const Vec& c, double r, double max_fraction, double tolerance) {
  const Vec rel = o - c;
  const double a = d.squaredNorm();
  const double b = rel.dot(d);
  if (!(a > 0.0) || b >= 0.0) return {};  // a point, or moving away from the centre
  // Closest approach first: |p| carries the rounding of |rel|, not of |rel|^2.
  const double closest = -b / a;
  const Vec p = rel + closest * d;
  const double pp = p.squaredNorm();
  if (std::sqrt(pp) > r + tolerance) return {};
  const double t = std::max(closest - std::sqrt(std::max(r * r - pp, 0.0) / a), 0.0);
  if (t > max_fraction) return {};
  const Vec at = rel + t * d;
  return {CastStatus::hit, t, safe_unit(at), std::max(std::sqrt(pp) - r, 0.0), 0};
}

LocalHit ray_sphere(const Sphere& s, const Vec& o, const Vec& d, double max_fraction, double tolerance) {
  const double r = s.radius + s.margin;
  if (o.norm() <= r + tolerance) return inside();
  return ray_ball(o, d, Vec::Zero(), r, max_fraction, tolerance);
}

// The capsule is the union of the two end balls and the side of the finite
// cylinder between them (its caps lie inside the balls), so the first entry
// is the earliest entry into one of the three.
LocalHit ray_capsule(const Capsule& s, const Vec& o, const Vec& d, double max_fraction, double tolerance) {
  const double r = s.radius + s.margin, h = s.half_length;
  const Vec on_axis(0.0, 0.0, std::clamp(o.z(), -h, h));
  if ((o - on_axis).norm() <= r + tolerance) return inside();
  LocalHit best;
  for (const double end : {-h, h}) {
    const LocalHit cap = ray_ball(o, d, Vec(0.0, 0.0, end), r, max_fraction, tolerance);
    if (cap.status == CastStatus::hit && (best.status != CastStatus::hit || cap.fraction < best.fraction)) best = cap;
  }
  const double a = d.x() * d.x() + d.y() * d.y();
  const double b = o.x() * d.x() + o.y() * d.y();
  if (a > 0.0 && b < 0.0) {
    const double closest = -b / a;
    const double px = o.x() + closest * d.x(), py = o.y() + closest * d.y();
    const double pp = px * px + py * py;
    const double t = closest - std::sqrt(std::max(r * r - pp, 0.0) / a);
    const double z = o.z() + t * d.z();
    if (std::sqrt(pp) <= r + tolerance && t >= 0.0 && t <= max_fraction && std::abs(z) <= h &&
        (best.status != CastStatus::hit || t < best.fraction))
      best = {CastStatus::hit, t, safe_unit(Vec(o.x() + t * d.x(), o.y() + t * d.y(), 0.0)),
              std::max(std::sqrt(pp) - r, 0.0), 0};
  }
  return best;
}

// Slab test: the ray enters the box when it has entered all three slabs.
// A ray parallel to a slab (d_i = 0) is inside it for every t or never:
// rays along a face or an edge (|o_i| = h_i) stay on it and hit.
LocalHit ray_box(const Box& s, const Vec& o, const Vec& d, double max_fraction, double tolerance) {
  const Vec& h = s.half_extents;
  if ((o.cwiseAbs() - h).maxCoeff() <= tolerance) return inside();
  double enter = -std::numeric_limits<double>::infinity(), leave = max_fraction;
  int axis = -1;  // the slab entered last: its face is the one hit
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) {
      if (std::abs(o[i]) > h[i]) return {};
      continue;
    }
    double t0 = (-h[i] - o[i]) / d[i], t1 = (h[i] - o[i]) / d[i];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > enter) {
      enter = t0;
      axis = i;
    }
    leave = std::min(leave, t1);
  }
  // o is outside some slab i (|o_i| > h_i, d_i != 0): the ray is inside it
  // over [t0, t1], which excludes 0. Both after 0: enter >= t0 > 0; both
  // before (moving away from the slab): leave <= t1 < 0, a miss, even when
  // the other slabs make enter <= leave.
  if (axis < 0 || enter > leave || leave < 0.0) return {};
  enter = std::max(enter, 0.0);
  Vec n = Vec::Zero();
  n[axis] = d[axis] > 0.0 ? -1.0 : 1.0;
  return {CastStatus::hit, enter, n, 0.0, 0};
}

// The cylinder |z| <= h, x^2 + y^2 <= r^2 is the slab |z| <= h intersected
// with the infinite cylinder: the ray enters it when it has entered both
// (the later entry; its surface gives the normal), as in the slab test. The
// side's interval comes from the closest approach to the axis, as for a
// ball; a ray passing within the tolerance of the side touches it there.
LocalHit ray_cylinder(const Cylinder& s, const Vec& o, const Vec& d, double max_fraction, double tolerance) {
  const double r = s.radius, h = s.half_length;
  // (Plain square roots: coordinates are within 1e60 and sizes above 1e-60.)
  const double rho = std::sqrt(o.x() * o.x() + o.y() * o.y());
  if (std::abs(o.z()) <= h + tolerance && rho <= r + tolerance) return inside();
  const double inf = std::numeric_limits<double>::infinity();
  // The slab.
  double cap_enter = -inf, cap_leave = inf;
  if (d.z() != 0.0) {
    cap_enter = (-h - o.z()) / d.z();
    cap_leave = (h - o.z()) / d.z();
    if (cap_enter > cap_leave) std::swap(cap_enter, cap_leave);
  } else if (std::abs(o.z()) > h) {
    return {};
  }
  // The side.
  double side_enter = -inf, side_leave = inf, graze = 0.0;
  const double a = d.x() * d.x() + d.y() * d.y();
  if (a > 0.0) {
    const double closest = -(o.x() * d.x() + o.y() * d.y()) / a;
    const double px = o.x() + closest * d.x(), py = o.y() + closest * d.y();
    const double p = std::sqrt(px * px + py * py);
    if (p > r + tolerance) return {};
    const double half = std::sqrt(std::max(r - p, 0.0) * (r + p) / a);
    side_enter = closest - half;
    side_leave = closest + half;
    graze = std::max(p - r, 0.0);
  } else if (rho > r) {
    return {};
  }
  const double enter = std::max(cap_enter, side_enter), leave = std::min({cap_leave, side_leave, max_fraction});
  // o is outside the slab or the side, so (as in ray_box) a hit enters at or after 0.
  if (enter > leave || leave < 0.0) return {};
  const double t = std::max(enter, 0.0);
  if (side_enter >= cap_enter) {
    const Vec at = o + t * d;
    return {CastStatus::hit, t, safe_unit(Vec(at.x(), at.y(), 0.0)), graze, 0};
  }
  return {CastStatus::hit, t, Vec(0.0, 0.0, d.z() > 0.0 ? -1.0 : 1.0), 0.0, 0};
}

// Every other shape: GJK ray cast on the core, grown by its radius. A stall
// or the cap before its first clip certifies nothing of the start
// (gjk_raycast.hpp), so penetration() settles it: started inside, or one
// more ray cast from the certified direction toward the origin, whose
// support faces the ray (a stall there leaves fraction 0, now known to be
// free). Without a verdict the stall stands.
template <class S>
LocalHit ray_gjk(const S& shape, const Vec& o, const Vec& d, double max_fraction, double tolerance,
                 const RaycastSettings& settings) {
  const auto core = core_of(shape);
  const FixedPoint origin{o};
  const double radius = core_radius(shape);
  GjkRaycastResult g = gjk_raycast(core, origin, radius, d, max_fraction, o, tolerance, settings.max_iterations);
  int iterations = g.iterations;
  if (start_unsettled(g)) {
    // The origin as a point (a ball of radius 0) in the shape's frame.
    const cast_detail::Start start = cast_detail::settle_start(
        shape, Pose::identity(), Sphere{0.0, 0.0}, Pose::from_translation(o + core_offset(shape)), 0.0, tolerance);
    if (start.within) return {CastStatus::initially_overlapping, 0.0, Vec::Zero(), 0.0, iterations};
    if (start.apart) {
      g = gjk_raycast(core, origin, radius, d, max_fraction, start.p.normal, tolerance, settings.max_iterations);
      iterations += g.iterations;
    }
  }
  return {g.status, g.lambda, g.normal, std::max(g.gap, 0.0), iterations};
}

template <class S>
LocalHit ray_local(const S& shape, const Vec& o, const Vec& d, double max_fraction, double tolerance,
                   const RaycastSettings& settings) {
  return ray_gjk(shape, o, d, max_fraction, tolerance, settings);
}
LocalHit ray_local(const Sphere& s, const Vec& o, const Vec& d, double max_fraction, double tolerance,
                   const RaycastSettings&) {
  return ray_sphere(s, o, d, max_fraction, tolerance);
}
LocalHit ray_local(const Capsule& s, const Vec& o, const Vec& d, double max_fraction, double tolerance,
                   const RaycastSettings&) {
  return ray_capsule(s, o, d, max_fraction, tolerance);
}
// A rounded cylinder's edge is a torus (a quartic): GJK.
LocalHit ray_local(const Cylinder& s, const Vec& o, const Vec& d, double max_fraction, double tolerance,
                   const RaycastSettings& settings) {
  if (s.margin > 0.0) return ray_gjk(s, o, d, max_fraction, tolerance, settings);
  return ray_cylinder(s, o, d, max_fraction, tolerance);
}
LocalHit ray_local(const Box& s, const Vec& o, const Vec& d, double max_fraction, double tolerance,
                   const RaycastSettings& settings) {
  if (s.margin > 0.0) return ray_gjk(s, o, d, max_fraction, tolerance, settings);
  return ray_box(s, o, d, max_fraction, tolerance);
}

bool finite_within(const Vec& x) { return x.allFinite() && x.cwiseAbs().maxCoeff() <= max_coordinate; }

bool ray_valid(const Shape& shape, const Pose& pose, const Vec& origin, const Vec& direction, double max_fraction) {
  if (!pose.valid() || !validate(shape).ok() || !finite_within(origin) || !finite_within(direction)) return false;
  if (!(direction.cwiseAbs().maxCoeff() > 0.0)) return false;  // a zero direction is no ray
  if (!(max_fraction >= 0.0) || !std::isfinite(max_fraction)) return false;
  if (!finite_within(max_fraction * direction)) return false;
  const double size = bounding_radius(shape);
  return size == 0.0 || size >= min_pair_extent;  // squares of smaller lengths underflow (see query.hpp)
}

}  // namespace

RaycastResult raycast(const Shape& shape, const Pose& pose, const Eigen::Vector3d& origin,
                      const Eigen::Vector3d& direction, double max_fraction, const RaycastSettings& settings) {
  RaycastResult out;
  if (!ray_valid(shape, pose, origin, direction, max_fraction)) {
    out.status = CastStatus::invalid_input;
    return out;
  }
  const LocalHit local = std::visit(
      [&](const auto& s) {
        // The ray in the core's frame: world differences first (exact for a
        // nearby ray), then the small offset.
        const Vec o = pose.rotation.transpose() * (origin - pose.translation) - core_offset(s);
        const Vec d = pose.rotation.transpose() * direction;
        const double size = bounding_radius(s);
        const double rounding = 32.0 * std::numeric_limits<double>::epsilon() * (size + o.norm());
        const double tolerance = std::max(settings.tolerance * size, rounding);
        return ray_local(s, o, d, max_fraction, tolerance, settings);
      },
      shape);
  out.status = local.status;
  out.iterations = local.iterations;
  out.hit = local.status == CastStatus::hit || local.status == CastStatus::initially_overlapping;
  out.started_inside = local.status == CastStatus::initially_overlapping;
  out.fraction = local.status == CastStatus::separated ? max_fraction : local.fraction;
  if (out.hit) {
    out.point = origin + out.fraction * direction;
    out.normal = pose.rotation * local.normal;
    out.error_bound = local.error_bound;
  }
  return out;
}

}  // namespace hedra::collision
