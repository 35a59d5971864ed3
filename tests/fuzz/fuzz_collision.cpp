// Fuzz target: intersect / distance / penetration / contact, and the
// continuous queries (raycast, shape_cast, time_of_impact), on arbitrary
// shapes, poses and motions.
//
// The bytes choose two shapes (sphere, box, capsule, cylinder, cone or a hull
// of up to 12 points, each with a margin), their sizes (sometimes negative,
// NaN or infinite, spanning 1e-4 .. 1e4), and two poses (quaternions that
// may be zero or NaN, translations up to 1e6; sometimes B's rotation A's
// turned by 1e-1 .. 1e-15 rad, a nearly coaxial pair; from a byte after
// everything else, B near A's axis and tilted 1e-2 .. 1e-10 rad off it, a
// peg in a hole; from a byte after that, B's rotation scaled, sheared or
// mirrored: not a rigid motion). Checked, for every
// input and both orders (A, B) and (B, A):
//   - every output field is finite, whatever the status;
//   - invalid shapes or poses, or a pair below min_pair_extent, give
//     invalid_input; valid ones never do;
//   - when both orders answer ok: the distances agree within the pair's
//     tolerance plus the reported error bounds, and so do the signed
//     penetration distances; intersect agrees with them away from touching;
//   - ok answers keep point_b - point_a = distance * normal and a unit normal;
//   - cached frames: contact() and penetration() warm over two nearby
//     frames agree with cold ones (contact: within the face bias);
//   - box pairs: contact()'s box path equals the general polytope path, a
//     still pair's cached answer equals its first, a moved one's warm answer
//     the cold one within the face bias;
//   - contact(): at most four points, every point and depth finite, its
//     error bound >= 0 and, when finite, within it of penetration()'s
//     distance (and that one's bound); when it
//     and penetration() both answer ok, it says intersecting when the pair
//     is deeper than the face bias of manifold.hpp, and a separation it
//     reports is at most the signed distance plus that bias.
// The continuous queries (bytes read after all of the above, so older inputs
// decode to the same pair; when they run dry, A sweeps through B's centre
// and a ray goes from A's origin through B's): a ray against B, A cast
// against B, and A swept with rotation against B. Checked:
//   - every output is finite and the status one of the enum's; invalid
//     input exactly when an input is out of range;
//   - the fraction lies in [0, max_fraction] (casts: [0, 1]);
//   - never late: at sampled fractions before the reported one (and at the
//     end for a miss) penetration() never certifies the pair (the ray's
//     point) within the target by more than the tolerance;
//   - a hit: the signed distance at the fraction is within the tolerance
//     plus the query's and penetration()'s error bounds of the target.
// The tolerance is 1e-9 of the pair's size plus the rounding of its world
// coordinates (64 eps of the largest coordinate, motions included).
// Halfspaces (halfspace.hpp): B against the halfspace z <= margin of A's
// pose (a margin from a byte read after everything else), checked by
// check_halfspace() below.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <hedra/collision/cast.hpp>
#include <hedra/collision/detail/minkowski.hpp>  // core_offset
#include <hedra/collision/halfspace.hpp>
#include <hedra/collision/manifold.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/raycast.hpp>
#include <hedra/collision/time_of_impact.hpp>
#include <limits>
#include <optional>
#include <variant>
#include <vector>

#include "../../collision/src/box_box.hpp"
#include "fuzz_input.hpp"

namespace {

using hedra::collision::Pose;
using hedra::collision::Shape;
using hedra::collision::Status;
using Vec = Eigen::Vector3d;

double size_value(hedra::fuzz::FuzzInput& in, bool allow_bad) {
  if (allow_bad && in.byte() % 16 == 0) return in.any_double();  // negative, NaN, inf, 1e300...
  const double mantissa = 0.05 + std::fabs(in.finite_double(8.0));
  const int decade = static_cast<int>(in.byte() % 9) - 4;  // 1e-4 .. 1e4
  return mantissa * std::pow(10.0, decade);
}

bool make_shape(hedra::fuzz::FuzzInput& in, Shape& shape) {
  const bool allow_bad = in.byte() % 8 == 0;
  const double margin = (in.byte() % 4 == 0) ? size_value(in, allow_bad) * 0.1 : 0.0;
  switch (in.byte() % 6) {
    case 0:
      shape = hedra::collision::Sphere{size_value(in, allow_bad), margin};
      return true;
    case 1:
      shape = hedra::collision::Box{
          Vec{size_value(in, allow_bad), size_value(in, allow_bad), size_value(in, allow_bad)}, margin};
      return true;
    case 2: {
      const double half_length = size_value(in, allow_bad);  // read first: the corpora's byte order
      shape = hedra::collision::Capsule{size_value(in, allow_bad), half_length, margin};
      return true;
    }
    case 3:
      shape = hedra::collision::Cylinder{size_value(in, allow_bad), size_value(in, allow_bad), margin};
      return true;
    case 4:
      shape = hedra::collision::Cone{size_value(in, allow_bad), size_value(in, allow_bad), margin};
      return true;
    default: {
      const double scale = size_value(in, false);
      std::vector<Vec> points(1 + in.byte() % 12);
      for (Vec& p : points) p = Vec{in.finite_double(4.0), in.finite_double(4.0), in.finite_double(4.0)} * scale;
      const auto built = hedra::collision::ConvexPolyhedron::build(points);
      if (!built.ok()) {
        // Only a widest span under hull::min_input_extent (coordinates that
        // came out tiny) may refuse a hull of finite points.
        Vec lo = points[0], hi = points[0];
        for (const Vec& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
        const double widest = (hi - lo).maxCoeff();
        HEDRA_FUZZ_CHECK(widest > 0.0 && widest < hedra::hull::min_input_extent,
                         "hull of %zu finite points spanning %g failed: %s", points.size(), widest,
                         built.message.c_str());
        shape = hedra::collision::Sphere{scale, margin};
        return true;
      }
      shape = hedra::collision::Polyhedron{built.polyhedron, margin};
      return true;
    }
  }
}

// Every multi-value read below is a braced list, evaluated left to right:
// the arguments of a call are evaluated in an unspecified order (GCC right
// to left, clang left to right), and the GCC replay driver then decoded a
// libFuzzer finding into another pair.
// Whether p's rotation is one by pose.hpp's definition, computed apart from
// Pose::is_rotation(): max |R^T R - I| <= rotation_tolerance and det R > 0;
// nothing within 1e-12 of the tolerance (rounding decides there).
std::optional<bool> rigid(const Pose& p) {
  if (!p.rotation.allFinite()) return false;
  const double error = (p.rotation.transpose() * p.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!std::isfinite(error)) return false;
  if (std::abs(error - hedra::collision::rotation_tolerance) < 1e-12) return std::nullopt;
  return error <= hedra::collision::rotation_tolerance && p.rotation.determinant() > 0.0;
}

Pose make_pose(hedra::fuzz::FuzzInput& in) {
  Eigen::Quaterniond q;
  if (in.byte() % 16 == 0) {
    q = Eigen::Quaterniond{in.any_double(), in.any_double(), in.any_double(), in.any_double()};
  } else {
    q = Eigen::Quaterniond{in.finite_double(2.0), in.finite_double(2.0), in.finite_double(2.0), in.finite_double(2.0)};
    if (q.squaredNorm() == 0.0) q = Eigen::Quaterniond::Identity();
  }
  Vec t{in.finite_double(8.0), in.finite_double(8.0), in.finite_double(8.0)};
  if (in.byte() % 8 == 0) t += Vec::Constant(std::pow(10.0, in.byte() % 7));  // up to 1e6 from the origin
  if (in.byte() % 32 == 0) t.x() = in.any_double();
  return Pose::from_quaternion(q, t);
}

bool finite(const Vec& v) { return v.allFinite(); }

// Replaying a finding (HEDRA_FUZZ_VERBOSE set): the pair at full precision.
struct Describe {
  void operator()(const hedra::collision::Sphere& s) const { std::fprintf(stderr, "sphere r=%.17g", s.radius); }
  void operator()(const hedra::collision::Box& s) const {
    std::fprintf(stderr, "box h=(%.17g, %.17g, %.17g)", s.half_extents.x(), s.half_extents.y(), s.half_extents.z());
  }
  void operator()(const hedra::collision::Capsule& s) const {
    std::fprintf(stderr, "capsule h=%.17g r=%.17g", s.half_length, s.radius);
  }
  void operator()(const hedra::collision::Cylinder& s) const {
    std::fprintf(stderr, "cylinder r=%.17g h=%.17g", s.radius, s.half_length);
  }
  void operator()(const hedra::collision::Cone& s) const {
    std::fprintf(stderr, "cone r=%.17g h=%.17g", s.radius, s.half_length);
  }
  void operator()(const hedra::collision::Polyhedron& s) const {
    std::fprintf(stderr, "hull of %zu vertices:", s.hull->vertex_count());
    for (const Vec& v : s.hull->vertices()) {
      const Vec p = v + s.hull->offset();
      std::fprintf(stderr, " {%.17g, %.17g, %.17g}", p.x(), p.y(), p.z());
    }
  }
};

void describe(const char* name, const Shape& s, const Pose& pose) {
  std::fprintf(stderr, "%s: ", name);
  std::visit(Describe{}, s);
  std::visit([](const auto& shape) { std::fprintf(stderr, " margin=%.17g", shape.margin); }, s);
  const Eigen::Quaterniond q(pose.rotation);
  std::fprintf(stderr, "\n  q=(%.17g, %.17g, %.17g, %.17g) t=(%.17g, %.17g, %.17g)\n", q.w(), q.x(), q.y(), q.z(),
               pose.translation.x(), pose.translation.y(), pose.translation.z());
}

template <class Result>
void check_geometry(const Result& r, double tol, const char* what) {
  HEDRA_FUZZ_CHECK(std::isfinite(r.distance) && std::isfinite(r.error_bound) && finite(r.normal) && finite(r.point_a) &&
                       finite(r.point_b),
                   "%s: non-finite output (status %s)", what, to_string(r.status));
  if (r.status != Status::ok) return;
  const bool has_normal = r.normal.squaredNorm() > 0.0;
  if (has_normal) {
    HEDRA_FUZZ_CHECK(std::fabs(r.normal.norm() - 1.0) < 1e-9, "%s: normal of length %.17g", what, r.normal.norm());
    const Vec gap = r.point_b - r.point_a - r.distance * r.normal;
    HEDRA_FUZZ_CHECK(gap.norm() <= tol + r.error_bound, "%s: point_b - point_a - distance*normal = %.3g (tol %.3g)",
                     what, gap.norm(), tol);
  }
}

// ---- continuous queries ------------------------------------------------------

using hedra::collision::CastResult;
using hedra::collision::CastStatus;

// The motions of the continuous queries, decoded after every other byte.
struct Motion {
  Vec move_a = Vec::Zero(), move_b = Vec::Zero();  // translations over the step
  Vec axis = Vec::UnitZ();                         // A's turn over the step (time_of_impact)
  double angle = 0.0;
  Vec ray_origin = Vec::Zero(), ray_direction = Vec::Zero();
  double max_fraction = 1.0;
  double target_distance = 0.0, linear_slop = 0.0;
};

Motion make_motion(hedra::fuzz::FuzzInput& in, const Pose& pose_a, const Pose& pose_b, double size) {
  Motion m;
  const double scale = std::pow(10.0, static_cast<int>(in.byte() % 9) - 4);
  m.move_a = Vec{in.finite_double(8.0), in.finite_double(8.0), in.finite_double(8.0)} * scale;
  m.move_b = Vec{in.finite_double(8.0), in.finite_double(8.0), in.finite_double(8.0)} * scale;
  const Vec through = pose_b.translation - pose_a.translation;
  if (m.move_a.isZero(0.0) && m.move_b.isZero(0.0)) m.move_a = 2.0 * through;  // A sweeps through B
  m.angle = in.finite_double(4.0);
  Vec axis{in.finite_double(1.0), in.finite_double(1.0), in.finite_double(1.0)};
  const double largest = axis.cwiseAbs().maxCoeff();  // (scaled first, as for the coaxial turn)
  if (largest > 0.0) m.axis = Vec(axis / largest).normalized();
  m.ray_origin = pose_a.translation;
  m.ray_direction = 2.0 * through + Vec{in.finite_double(8.0), in.finite_double(8.0), in.finite_double(8.0)} * scale;
  switch (in.byte() % 4) {
    case 0:
      break;
    case 1:
      m.max_fraction = 0.5;
      break;
    case 2:
      m.max_fraction = 10.0;
      break;
    default:
      m.max_fraction = std::fabs(in.finite_double(1e3));
  }
  const std::uint8_t target = in.byte();
  if (std::isfinite(size)) {
    if (target & 1) m.target_distance = 1e-2 * size;
    if (target & 2) m.linear_slop = 1e-3 * size;
  }
  return m;
}

bool within(const Vec& x) { return x.allFinite() && x.cwiseAbs().maxCoeff() <= hedra::collision::max_coordinate; }

bool status_known(CastStatus s) {
  switch (s) {
    case CastStatus::hit:
    case CastStatus::separated:
    case CastStatus::initially_overlapping:
    case CastStatus::max_iterations:
    case CastStatus::stalled:
    case CastStatus::degenerate:
    case CastStatus::invalid_input:
      return true;
  }
  return false;
}

// The signed distance of the pair (or a point: a sphere of radius 0) as an
// interval; empty (lower > upper) when penetration() gives no verdict.
struct Signed {
  double lower = 1.0, upper = 0.0;
};
Signed signed_distance(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b) {
  const hedra::collision::PenetrationResult p = penetration(a, pose_a, b, pose_b);
  if (p.status != Status::ok) return {};
  return {p.distance - p.error_bound, p.distance + p.error_bound};
}

// What every continuous answer keeps, given the signed distance at a
// fraction (`at`), the target and the tolerance: never late, a hit at the
// target, a start within it. `what` names the query.
template <class At>
void check_timeline(const char* what, CastStatus status, double fraction, double max_fraction, double error_bound,
                    double target, double tol, const At& at) {
  HEDRA_FUZZ_CHECK(fraction >= 0.0 && fraction <= max_fraction, "%s: fraction %.17g outside [0, %.17g] (%s)", what,
                   fraction, max_fraction, to_string(status));
  if (status == CastStatus::initially_overlapping) {
    HEDRA_FUZZ_CHECK(fraction == 0.0, "%s: started within the target at fraction %.17g", what, fraction);
    const Signed d = at(0.0);
    HEDRA_FUZZ_CHECK(d.lower > d.upper || d.lower <= target + tol,
                     "%s: starts within the target %.17g but the distance is >= %.17g (tol %.3g)", what, target,
                     d.lower, tol);
    return;
  }
  if (status == CastStatus::degenerate || status == CastStatus::invalid_input) return;
  // Safe: no contact before `fraction` (nor at it, nor anywhere on a miss).
  for (const double s : {0.0, 0.5, 0.9, 0.999, 1.0}) {
    const Signed d = at(s * fraction);
    HEDRA_FUZZ_CHECK(d.lower > d.upper || d.upper >= target - tol,
                     "%s: late: at %.17g (reported %.17g, %s) the distance is <= %.17g, target %.17g (tol %.3g)", what,
                     s * fraction, fraction, to_string(status), d.upper, target, tol);
  }
  if (status == CastStatus::separated) {
    HEDRA_FUZZ_CHECK(fraction == max_fraction, "%s: a miss at %.17g, not %.17g", what, fraction, max_fraction);
  }
  if (status == CastStatus::hit) {
    const Signed d = at(fraction);
    HEDRA_FUZZ_CHECK(d.lower > d.upper || d.lower <= target + error_bound + tol,
                     "%s: a hit at %.17g where the distance is >= %.17g, target %.17g (bound %.3g, tol %.3g)", what,
                     fraction, d.lower, target, error_bound, tol);
  }
}

void check_cast_fields(const CastResult& r, const char* what) {
  HEDRA_FUZZ_CHECK(status_known(r.status), "%s: unknown status %d", what, static_cast<int>(r.status));
  HEDRA_FUZZ_CHECK(std::isfinite(r.fraction) && std::isfinite(r.distance) && std::isfinite(r.error_bound) &&
                       r.error_bound >= 0.0 && finite(r.normal) && finite(r.point_a) && finite(r.point_b),
                   "%s: non-finite output (status %s)", what, to_string(r.status));
  HEDRA_FUZZ_CHECK(r.hit == (r.status == CastStatus::hit || r.status == CastStatus::initially_overlapping) &&
                       r.initially_overlapping == (r.status == CastStatus::initially_overlapping),
                   "%s: flags disagree with the status %s", what, to_string(r.status));
  if (r.status == CastStatus::hit) {
    HEDRA_FUZZ_CHECK(std::fabs(r.normal.norm() - 1.0) < 1e-9, "%s: normal of length %.17g", what, r.normal.norm());
  }
}

void check_raycast(const Shape& b, const Pose& pose_b, const Motion& m, double coordinates) {
  const hedra::collision::RaycastResult r = raycast(b, pose_b, m.ray_origin, m.ray_direction, m.max_fraction);
  if (std::getenv("HEDRA_FUZZ_VERBOSE") != nullptr) {
    std::fprintf(stderr, "raycast %s at %.17g\n", to_string(r.status), r.fraction);
  }
  HEDRA_FUZZ_CHECK(status_known(r.status), "raycast: unknown status %d", static_cast<int>(r.status));
  HEDRA_FUZZ_CHECK(std::isfinite(r.fraction) && std::isfinite(r.error_bound) && r.error_bound >= 0.0 &&
                       finite(r.point) && finite(r.normal),
                   "raycast: non-finite output (status %s)", to_string(r.status));
  const double size = bounding_radius(b);
  const bool valid = validate(b).ok() && pose_b.valid() && within(m.ray_origin) && within(m.ray_direction) &&
                     m.ray_direction.cwiseAbs().maxCoeff() > 0.0 && within(m.max_fraction * m.ray_direction) &&
                     (size == 0.0 || size >= hedra::collision::min_pair_extent);
  HEDRA_FUZZ_CHECK(valid == (r.status != CastStatus::invalid_input), "raycast: %s for %s input", to_string(r.status),
                   valid ? "valid" : "invalid");
  if (!valid) return;
  HEDRA_FUZZ_CHECK(r.hit == (r.status == CastStatus::hit || r.status == CastStatus::initially_overlapping) &&
                       r.started_inside == (r.status == CastStatus::initially_overlapping),
                   "raycast: flags disagree with the status %s", to_string(r.status));
  const double reach = m.ray_origin.norm() + (m.max_fraction * m.ray_direction).norm();
  const double tol = 1e-9 * size + 64.0 * std::numeric_limits<double>::epsilon() * std::max(coordinates, reach);
  const hedra::collision::Sphere point{0.0, 0.0};
  check_timeline("raycast", r.status, r.fraction, m.max_fraction, r.error_bound, 0.0, tol, [&](double t) {
    return signed_distance(b, pose_b, point, Pose::from_translation(m.ray_origin + t * m.ray_direction));
  });
}

void check_casts(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, const Motion& m, bool valid,
                 double size, double coordinates) {
  hedra::collision::ShapeCastSettings cast_settings;
  cast_settings.target_distance = m.target_distance;
  cast_settings.linear_slop = m.linear_slop;
  const CastResult cast = shape_cast(a, pose_a, m.move_a, b, pose_b, m.move_b, nullptr, cast_settings);
  const hedra::collision::Sweep sweep_a{
      pose_a, {Eigen::AngleAxisd(m.angle, m.axis).toRotationMatrix() * pose_a.rotation, pose_a.translation + m.move_a}};
  const hedra::collision::Sweep sweep_b{pose_b, {pose_b.rotation, pose_b.translation + m.move_b}};
  hedra::collision::ToiSettings toi_settings;
  toi_settings.target_distance = m.target_distance;
  toi_settings.linear_slop = m.linear_slop;
  const CastResult toi = time_of_impact(a, sweep_a, b, sweep_b, nullptr, toi_settings);
  if (std::getenv("HEDRA_FUZZ_VERBOSE") != nullptr) {
    std::fprintf(stderr, "shape_cast %s at %.17g, time_of_impact %s at %.17g (%d steps)\n", to_string(cast.status),
                 cast.fraction, to_string(toi.status), toi.fraction, toi.iterations);
  }
  check_cast_fields(cast, "shape_cast");
  check_cast_fields(toi, "time_of_impact");
  const bool cast_valid = valid && within(m.move_a) && within(m.move_b);
  const bool toi_valid = valid && sweep_a.end.valid() && sweep_b.end.valid();
  HEDRA_FUZZ_CHECK(cast_valid == (cast.status != CastStatus::invalid_input), "shape_cast: %s for %s input",
                   to_string(cast.status), cast_valid ? "valid" : "invalid");
  HEDRA_FUZZ_CHECK(toi_valid == (toi.status != CastStatus::invalid_input), "time_of_impact: %s for %s input",
                   to_string(toi.status), toi_valid ? "valid" : "invalid");
  const double motion = std::max(m.move_a.norm(), m.move_b.norm());
  const double tol = 1e-9 * size + 64.0 * std::numeric_limits<double>::epsilon() * (coordinates + motion);
  const double target = m.target_distance + m.linear_slop;
  if (cast_valid) {
    check_timeline("shape_cast", cast.status, cast.fraction, 1.0, cast.error_bound, target, tol, [&](double t) {
      return signed_distance(a, Pose{pose_a.rotation, pose_a.translation + t * m.move_a}, b,
                             Pose{pose_b.rotation, pose_b.translation + t * m.move_b});
    });
  }
  if (toi_valid) {
    check_timeline("time_of_impact", toi.status, toi.fraction, 1.0, toi.error_bound, target, tol, [&](double t) {
      return signed_distance(a, hedra::collision::pose_at(sweep_a, t), b, hedra::collision::pose_at(sweep_b, t));
    });
  }
}

}  // namespace

// Cached frames: contact() and penetration() carried over two frames with
// their caches (B turned by 1e-5 rad about the motion's axis and moved by
// 1e-5 of the size along it in between), the warm answers checked against
// cold ones at the same poses: the same invariants, and a warm manifold's
// distance within the face bias (a cached face kept while certified within
// it, manifold.hpp; each one's deepest point within it of its axis) of the
// cold one's when both overlap.
void check_cached_frames(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, const Motion& motion,
                         double tol, double size_scale) {
  hedra::collision::ContactCache contact_cache;
  hedra::collision::GjkCache gjk_cache;
  const hedra::collision::ContactSettings settings;
  Pose next = pose_b;
  next.rotation = Eigen::AngleAxisd(1e-5, motion.axis).toRotationMatrix() * pose_b.rotation;
  next.translation += 1e-5 * size_scale * motion.axis;
  const Pose* frames[] = {&pose_b, &next};
  for (const Pose* frame : frames) {
    const hedra::collision::ContactResult warm = contact(a, pose_a, b, *frame, &contact_cache);
    const hedra::collision::ContactResult cold = contact(a, pose_a, b, *frame);
    const hedra::collision::PenetrationResult p_warm = penetration(a, pose_a, b, *frame, &gjk_cache);
    const hedra::collision::PenetrationResult p_cold = penetration(a, pose_a, b, *frame);
    HEDRA_FUZZ_CHECK(warm.count >= 0 && warm.count <= hedra::collision::kMaxContactPoints, "warm contact count %d",
                     warm.count);
    HEDRA_FUZZ_CHECK(
        std::isfinite(warm.distance) && finite(warm.normal) && finite(warm.point_a) && finite(warm.point_b),
        "warm contact: non-finite output (status %s)", to_string(warm.status));
    for (int k = 0; k < warm.count; ++k)
      HEDRA_FUZZ_CHECK(finite(warm.points[k].point) && std::isfinite(warm.points[k].depth),
                       "warm contact point %d non-finite", k);
    HEDRA_FUZZ_CHECK((warm.status == Status::invalid_input) == (cold.status == Status::invalid_input),
                     "warm contact status %s, cold %s", to_string(warm.status), to_string(cold.status));
    const double bias = settings.relative_bias * std::fabs(cold.distance) + settings.absolute_bias * 2.0 * size_scale;
    if (warm.status == Status::ok && cold.status == Status::ok && warm.intersecting && cold.intersecting &&
        warm.path != hedra::collision::ContactPath::single_point &&
        cold.path != hedra::collision::ContactPath::single_point)
      HEDRA_FUZZ_CHECK(std::fabs(warm.distance - cold.distance) <= 2.0 * bias + tol,
                       "warm contact distance %.17g, cold %.17g (bias %.3g)", warm.distance, cold.distance, bias);
    if (p_warm.status == Status::ok && p_cold.status == Status::ok)
      HEDRA_FUZZ_CHECK(std::fabs(p_warm.distance - p_cold.distance) <= tol + p_warm.error_bound + p_cold.error_bound,
                       "warm penetration %.17g, cold %.17g", p_warm.distance, p_cold.distance);
  }
}

// B against the halfspace {z <= margin} of A's pose: invalid_input exactly
// for invalid input; otherwise finite outputs, the queries agree with each
// other, contact()'s deepest depth is the signed distance, every point's
// depth is its gap to the plane along the normal (within the contact
// distance), and the signed distance matches penetration() of B against a
// box 1e3 times B's size whose top face is the plane (GJK and EPA: an
// independent path).
void check_halfspace(const Shape& b, const Pose& pose_a, const Pose& pose_b, double margin, bool b_valid) {
  using namespace hedra::collision;
  const Halfspace h{Vec::UnitZ(), margin};
  const PenetrationResult p = penetration(h, pose_a, b, pose_b);
  ContactSettings settings;
  const double size = b_valid ? bounding_radius(b) : 0.0;
  settings.contact_distance = 0.01 * size;
  const ContactResult c = contact(h, pose_a, b, pose_b, nullptr, settings);
  const DistanceResult d = distance(h, pose_a, b, pose_b);
  const IntersectResult i = intersect(h, pose_a, b, pose_b);
  HEDRA_FUZZ_CHECK(std::isfinite(p.distance) && finite(p.normal) && finite(p.point_a) && finite(p.point_b) &&
                       std::isfinite(c.distance) && finite(c.normal) && c.count >= 0 && c.count <= kMaxContactPoints,
                   "halfspace: non-finite output (status %s)", to_string(p.status));
  for (int k = 0; k < c.count; ++k)
    HEDRA_FUZZ_CHECK(finite(c.points[k].point) && std::isfinite(c.points[k].depth), "halfspace point %d non-finite", k);
  const bool valid = b_valid && pose_a.valid() && pose_b.valid() && validate(h).ok();
  if (!valid) {
    HEDRA_FUZZ_CHECK(p.status == Status::invalid_input && c.status == Status::invalid_input &&
                         d.status == Status::invalid_input && i.status == Status::invalid_input,
                     "halfspace: invalid input answered %s", to_string(p.status));
    return;
  }
  // The pair-extent rule (halfspace.cpp): B's size or its distance to the plane.
  const Vec n = pose_a.rotation.col(2);
  const double extent = std::max(size, std::fabs(n.dot(pose_b.translation - pose_a.translation)));
  if (!(extent == 0.0 || extent >= min_pair_extent)) {
    HEDRA_FUZZ_CHECK(p.status == Status::invalid_input, "halfspace: out-of-range pair answered %s",
                     to_string(p.status));
    return;
  }
  HEDRA_FUZZ_CHECK(p.status == Status::ok && c.status == Status::ok && d.status == Status::ok && i.status == Status::ok,
                   "halfspace: valid input answered %s / %s", to_string(p.status), to_string(c.status));
  double offset = 0.0;
  if (const auto* poly = std::get_if<Polyhedron>(&b)) offset = poly->hull->offset().norm();
  const double coordinates = (pose_b.translation - pose_a.translation).norm() + offset + size + margin;
  const double tol = 1e-9 * size + 64.0 * std::numeric_limits<double>::epsilon() * coordinates;
  HEDRA_FUZZ_CHECK(std::fabs(p.normal.norm() - 1.0) < 1e-12, "halfspace normal of length %.17g", p.normal.norm());
  HEDRA_FUZZ_CHECK(std::fabs(c.distance - p.distance) <= tol, "halfspace: contact %.17g, penetration %.17g", c.distance,
                   p.distance);
  HEDRA_FUZZ_CHECK(i.intersecting == p.intersecting && d.intersecting == p.intersecting,
                   "halfspace: intersect / distance / penetration disagree");
  if (c.distance <= settings.contact_distance)
    HEDRA_FUZZ_CHECK(c.count >= 1, "halfspace: no point at %.17g", c.distance);
  double deepest = -INFINITY;
  for (int k = 0; k < c.count; ++k) {
    const ContactPoint& q = c.points[k];
    deepest = std::max(deepest, q.depth);
    HEDRA_FUZZ_CHECK(q.depth >= -settings.contact_distance - tol, "halfspace point %d at gap %.17g", k, -q.depth);
    const Vec on_a = q.point + (q.depth / 2.0) * c.normal;
    // World points: rounded at the scale of their coordinates.
    const double world = tol + 64.0 * std::numeric_limits<double>::epsilon() * pose_b.translation.norm();
    HEDRA_FUZZ_CHECK(std::fabs(n.dot(on_a - pose_a.translation) - margin) <= world,
                     "halfspace point %d: its witness on A is %.3g off the plane", k,
                     n.dot(on_a - pose_a.translation) - margin);
  }
  if (c.count > 0)
    HEDRA_FUZZ_CHECK(std::fabs(deepest + c.distance) <= tol, "halfspace: deepest %.17g, depth %.17g", deepest,
                     -c.distance);
  // The plane as a large box (sizes where GJK's tolerance of the box's size
  // stays well under the one checked).
  if (size < 1e-3 || size > 1e3 || coordinates > 1e4 * size || pose_b.translation.norm() > 1e4 * size ||
      std::fabs(p.distance) > 10.0 * size)
    return;
  const double L = 1e3 * size;
  const Vec foot = pose_b.translation - (n.dot(pose_b.translation - pose_a.translation) - margin) * n;
  const Pose box_pose{pose_a.rotation, foot - L * n};
  const PenetrationResult via_box = penetration(Box{Vec::Constant(L), 0.0}, box_pose, b, pose_b);
  if (via_box.status != Status::ok) return;
  HEDRA_FUZZ_CHECK(std::fabs(via_box.distance - p.distance) <= 1e-6 * L + via_box.error_bound,
                   "halfspace %.17g, the plane as a box %.17g", p.distance, via_box.distance);
}

// Box pairs (collision/src/box_box.cpp): the box path's answer `c` against
// the general polytope path's on the same pair (the same status, path and
// points within tol), and cached frames: the pair again (the answer from the
// cache, equal bit for bit), then B moved by 1e-7 of the size (rebuilt: the
// cold answer within the face bias).
void check_box_pair(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                    const hedra::collision::ContactResult& c, double tol) {
  hedra::collision::ContactSettings general;
  general.box_box_path = false;
  const hedra::collision::ContactResult g = contact(a, pose_a, b, pose_b, nullptr, general);
  HEDRA_FUZZ_CHECK(g.status == c.status && g.path == c.path && g.count == c.count,
                   "box path %s %s %d points, general path %s %s %d", to_string(c.status), to_string(c.path), c.count,
                   to_string(g.status), to_string(g.path), g.count);
  if (c.status != Status::ok) return;
  HEDRA_FUZZ_CHECK(std::fabs(g.distance - c.distance) <= tol, "box path distance %.17g, general path %.17g", c.distance,
                   g.distance);
  for (int k = 0; k < c.count; ++k) {  // in either order (equally deep points: rounding orders them)
    bool found = false;
    for (int j = 0; j < g.count; ++j)
      found = found || ((g.points[j].point - c.points[k].point).norm() <= tol &&
                        std::fabs(g.points[j].depth - c.points[k].depth) <= tol && g.points[j].id == c.points[k].id);
    HEDRA_FUZZ_CHECK(found, "box path point %d differs from the general path's", k);
  }
  hedra::collision::ContactCache cache;
  const hedra::collision::ContactSettings settings;
  const auto& box_a = std::get<hedra::collision::Box>(a);
  const auto& box_b = std::get<hedra::collision::Box>(b);
  hedra::collision::ContactResult first, again;
  if (!hedra::collision::detail::box_box_contact(box_a, pose_a, box_b, pose_b, &cache, settings, first)) return;
  // (Answers built on penetration()'s normal are not kept: GJK's warm start
  // moves with the cache.)
  if (!cache.box.valid) return;
  const bool recycled =
      hedra::collision::detail::box_box_contact(box_a, pose_a, box_b, pose_b, &cache, settings, again);
  HEDRA_FUZZ_CHECK(recycled && again.stats.cache_hit, "a still box pair not answered from its cache");
  HEDRA_FUZZ_CHECK(again.status == first.status && again.count == first.count && again.distance == first.distance &&
                       again.normal == first.normal,
                   "a still box pair's cached answer differs (%d / %d points, %.17g / %.17g)", again.count, first.count,
                   again.distance, first.distance);
  for (int k = 0; k < again.count; ++k)
    HEDRA_FUZZ_CHECK(again.points[k].point == first.points[k].point && again.points[k].depth == first.points[k].depth,
                     "a still box pair's cached point %d differs", k);
  const double size = std::max(bounding_radius(a), bounding_radius(b));
  Pose moved = pose_b;
  moved.translation += Vec(1e-7, -2e-7, 3e-7) * size;
  if (!moved.valid()) return;
  const hedra::collision::ContactResult warm = contact(a, pose_a, b, moved, &cache);
  const hedra::collision::ContactResult cold = contact(a, pose_a, b, moved);
  const double bias = settings.relative_bias * std::fabs(cold.distance) + settings.absolute_bias * 2.0 * size;
  HEDRA_FUZZ_CHECK(warm.status == cold.status && warm.count <= hedra::collision::kMaxContactPoints,
                   "a moved box pair: warm %s, cold %s", to_string(warm.status), to_string(cold.status));
  if (warm.status == Status::ok && cold.status == Status::ok)
    HEDRA_FUZZ_CHECK(std::fabs(warm.distance - cold.distance) <= bias + tol,
                     "a moved box pair: warm distance %.17g, cold %.17g", warm.distance, cold.distance);
}

// Overlapping box pairs (collision/src/sat_depth.cpp: SAT's 15 axes):
// penetration()'s answer `p` against the same boxes as hulls of their
// corners (GJK and EPA), within both error bounds and tol.
void check_box_depth(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                     const hedra::collision::PenetrationResult& p, double tol) {
  if (p.status != Status::ok || !p.intersecting) return;
  const auto as_hull = [](const hedra::collision::Box& box, Shape& out) {
    std::vector<Vec> corners;
    for (int i = 0; i < 8; ++i)
      corners.push_back(box.half_extents.cwiseProduct(Vec(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1)));
    const auto built = hedra::collision::ConvexPolyhedron::build(corners);
    if (!built.ok() || built.polyhedron->dimension() != 3) return false;
    out = hedra::collision::Polyhedron{built.polyhedron, box.margin};
    return true;
  };
  Shape hull_a, hull_b;
  if (!as_hull(std::get<hedra::collision::Box>(a), hull_a) || !as_hull(std::get<hedra::collision::Box>(b), hull_b))
    return;
  const hedra::collision::PenetrationResult e = penetration(hull_a, pose_a, hull_b, pose_b);
  if (e.status != Status::ok) return;
  HEDRA_FUZZ_CHECK(std::fabs(p.distance - e.distance) <= p.error_bound + e.error_bound + tol,
                   "box pair: penetration %.17g (bound %.3g), as hulls %.17g (bound %.3g)", p.distance, p.error_bound,
                   e.distance, e.error_bound);
  HEDRA_FUZZ_CHECK((p.point_b - p.point_a - p.distance * p.normal).norm() <= tol,
                   "box pair: witnesses off the normal by %.3g",
                   (p.point_b - p.point_a - p.distance * p.normal).norm());
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  hedra::fuzz::FuzzInput in(data, size);
  Shape a, b;
  make_shape(in, a);
  make_shape(in, b);
  const Pose pose_a = make_pose(in);
  Pose pose_b = make_pose(in);
  // Nearly coaxial pairs (tilted_revolution.hpp's branch and bound, and
  // EPA's rings of equal depths), which independent quaternions almost
  // never give: a trailing byte may make B's rotation A's turned by 1e-1 ..
  // 1e-15 rad about an axis from the bytes, sometimes also flipped end for
  // end. Read after everything else, so inputs without it decode as before.
  const std::uint8_t coaxial = in.byte();
  if (coaxial % 4 == 1 && pose_a.finite()) {
    const double angle = std::pow(10.0, -1.0 - static_cast<double>(in.byte() % 15));
    // Scaled by its largest coordinate first: a tiny axis (1e-163) has a
    // subnormal squared norm, normalises to a length 1e-8 off, and would
    // make a rotation that is not orthonormal (Pose's contract).
    Vec axis{in.finite_double(1.0), in.finite_double(1.0), in.finite_double(1.0)};
    const double largest = axis.cwiseAbs().maxCoeff();
    axis = largest > 0.0 ? Vec(axis / largest) : Vec::UnitX();
    pose_b.rotation = pose_a.rotation * Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
    if (coaxial & 4) pose_b.rotation = pose_b.rotation * Eigen::AngleAxisd(M_PI, Vec::UnitX()).toRotationMatrix();
  }
  // The continuous queries' motions: after every byte above.
  const double larger = std::max(bounding_radius(a), bounding_radius(b));
  const Motion motion = make_motion(in, pose_a, pose_b, larger);
  // Pegs in holes (revolution_polytope.hpp's branch and bound: a small core
  // deep inside a cylinder or cone, near its axis): a byte after all of the
  // above may put B's centre 1e-3 .. 1e-9 of the larger size off A's axis,
  // anywhere along it within A's size, and B's axis 1e-2 .. 1e-10 rad off
  // A's (one value of its low four bits, which no committed input had
  // there: they decode as before; the motion keeps its values).
  const std::uint8_t peg = in.byte();
  if (peg % 16 == 6 && pose_a.finite() && std::isfinite(larger)) {
    const double offset = std::pow(10.0, -3.0 - static_cast<double>(in.byte() % 7)) * larger;
    const double tilt = std::pow(10.0, -2.0 - static_cast<double>(in.byte() % 9));
    const double side = in.finite_double(4.0), turn = in.finite_double(4.0);
    const double along = in.finite_double(1.0) * bounding_radius(a);
    const Vec local{offset * std::cos(side), offset * std::sin(side), along};
    pose_b.translation = pose_a.translation + pose_a.rotation * local;
    pose_b.rotation =
        pose_a.rotation * Eigen::AngleAxisd(tilt, Vec(std::cos(turn), std::sin(turn), 0.0)).toRotationMatrix();
    if (peg & 16) pose_b.rotation = pose_b.rotation * Eigen::AngleAxisd(M_PI, Vec::UnitX()).toRotationMatrix();
  }
  // Transforms that are not rigid motions (Pose::valid()'s rotation check):
  // a byte after all of the above may distort B's rotation by 1 .. 1e-10
  // times a matrix from the bytes (scaled, sheared, or within the
  // tolerance), or mirror it (one value of its low three bits; older inputs
  // decode as before).
  // A distortion within the tolerance is accepted and answered for the
  // transform given, whose normals are unit only within the rotation's error
  // (pose.hpp): such inputs are not checked against this file's 1e-9
  // tolerances and end here; the others must answer invalid_input.
  const std::uint8_t distort = in.byte();
  const bool distorted = distort % 8 == 5;
  if (distorted) {
    if (distort & 8) {
      pose_b.rotation = pose_b.rotation * Vec(1.0, 1.0, -1.0).asDiagonal();
    } else {
      Eigen::Matrix3d shear;
      for (int k = 0; k < 9; ++k) shear(k / 3, k % 3) = in.finite_double(1.0);
      const double amount = std::pow(10.0, -static_cast<double>(in.byte() % 11));
      pose_b.rotation = pose_b.rotation * (Eigen::Matrix3d::Identity() + amount * shear);
    }
  }
  const std::optional<bool> rigid_b = rigid(pose_b);
  if (!rigid_b) return 0;  // within rounding of the tolerance: either verdict is right
  if (distorted && *rigid_b) return 0;
  if (std::getenv("HEDRA_FUZZ_VERBOSE") != nullptr) {
    describe("a", a, pose_a);
    describe("b", b, pose_b);
    std::fprintf(stderr,
                 "move_a=(%.17g, %.17g, %.17g) move_b=(%.17g, %.17g, %.17g) turn %.17g about (%.17g, %.17g, %.17g)\n"
                 "ray (%.17g, %.17g, %.17g) + t (%.17g, %.17g, %.17g), t <= %.17g; target %.17g + %.17g\n",
                 motion.move_a.x(), motion.move_a.y(), motion.move_a.z(), motion.move_b.x(), motion.move_b.y(),
                 motion.move_b.z(), motion.angle, motion.axis.x(), motion.axis.y(), motion.axis.z(),
                 motion.ray_origin.x(), motion.ray_origin.y(), motion.ray_origin.z(), motion.ray_direction.x(),
                 motion.ray_direction.y(), motion.ray_direction.z(), motion.max_fraction, motion.target_distance,
                 motion.linear_slop);
  }
  // Poses by their definition (pose.hpp), not by Pose::valid(): A's comes
  // from a quaternion (rigid whenever finite), B's may be distorted above.
  const auto translation_within = [](const Pose& p) {
    return p.translation.allFinite() && p.translation.cwiseAbs().maxCoeff() <= hedra::collision::max_coordinate;
  };
  bool valid = validate(a).ok() && validate(b).ok() && pose_a.rotation.allFinite() && translation_within(pose_a) &&
               *rigid_b && translation_within(pose_b);
  HEDRA_FUZZ_CHECK(pose_a.valid() == (pose_a.rotation.allFinite() && translation_within(pose_a)) &&
                       pose_b.valid() == (*rigid_b && translation_within(pose_b)),
                   "Pose::valid() disagrees with its definition (a %d, b %d)", pose_a.valid(), pose_b.valid());
  if (valid) {
    // The pair-extent rule of query.hpp, from its definition: the larger
    // bounding radius or the distance between the origins, zero or at least
    // min_pair_extent.
    const auto origin = [](const Shape& s, const Pose& pose) {
      return std::visit([&](const auto& shape) { return pose.apply(hedra::collision::core_offset(shape)); }, s);
    };
    const double extent = std::max({hedra::collision::bounding_radius(a), hedra::collision::bounding_radius(b),
                                    (origin(b, pose_b) - origin(a, pose_a)).cwiseAbs().maxCoeff()});
    valid = extent == 0.0 || extent >= hedra::collision::min_pair_extent;
  }

  const hedra::collision::IntersectResult i_ab = intersect(a, pose_a, b, pose_b);
  const hedra::collision::DistanceResult d_ab = distance(a, pose_a, b, pose_b);
  const hedra::collision::DistanceResult d_ba = distance(b, pose_b, a, pose_a);
  const hedra::collision::PenetrationResult p_ab = penetration(a, pose_a, b, pose_b);
  const hedra::collision::PenetrationResult p_ba = penetration(b, pose_b, a, pose_a);
  const hedra::collision::ContactResult c_ab = contact(a, pose_a, b, pose_b);

  if (std::getenv("HEDRA_FUZZ_VERBOSE") != nullptr) {
    std::fprintf(stderr, "intersect %d (%s, %d iterations)\n", i_ab.intersecting, to_string(i_ab.status),
                 i_ab.iterations);
    std::fprintf(stderr, "distance %.17g / %.17g (%s / %s)\n", d_ab.distance, d_ba.distance, to_string(d_ab.status),
                 to_string(d_ba.status));
    std::fprintf(stderr, "penetration %.17g / %.17g (%s / %s)\n", p_ab.distance, p_ba.distance, to_string(p_ab.status),
                 to_string(p_ba.status));
    std::fprintf(stderr, "contact %.17g, %d points (%s)\n", c_ab.distance, c_ab.count, to_string(c_ab.status));
  }
  HEDRA_FUZZ_CHECK(c_ab.count >= 0 && c_ab.count <= hedra::collision::kMaxContactPoints, "contact count %d",
                   c_ab.count);
  HEDRA_FUZZ_CHECK(std::isfinite(c_ab.distance) && finite(c_ab.normal) && finite(c_ab.point_a) && finite(c_ab.point_b),
                   "contact: non-finite output (status %s)", to_string(c_ab.status));
  for (int k = 0; k < c_ab.count; ++k) {
    HEDRA_FUZZ_CHECK(finite(c_ab.points[k].point) && std::isfinite(c_ab.points[k].depth),
                     "contact point %d non-finite (status %s)", k, to_string(c_ab.status));
  }
  // The contact's certified bound: never NaN or negative; where it and
  // penetration()'s are finite, their brackets of the exact signed distance meet.
  HEDRA_FUZZ_CHECK(c_ab.error_bound >= 0.0, "contact error bound %g", c_ab.error_bound);
  if (c_ab.status == Status::ok && p_ab.status == Status::ok && std::isfinite(c_ab.error_bound)) {
    HEDRA_FUZZ_CHECK(std::abs(c_ab.distance - p_ab.distance) <= c_ab.error_bound + p_ab.error_bound + 1e-9 * larger,
                     "contact distance %.17g +- %g, penetration %.17g +- %g", c_ab.distance, c_ab.error_bound,
                     p_ab.distance, p_ab.error_bound);
  }
  if (!valid) {
    HEDRA_FUZZ_CHECK(i_ab.status == Status::invalid_input && d_ab.status == Status::invalid_input &&
                         p_ab.status == Status::invalid_input && d_ba.status == Status::invalid_input &&
                         p_ba.status == Status::invalid_input && c_ab.status == Status::invalid_input,
                     "invalid input answered %s / %s / %s", to_string(i_ab.status), to_string(d_ab.status),
                     to_string(p_ab.status));
  } else {
    HEDRA_FUZZ_CHECK(i_ab.status != Status::invalid_input && d_ab.status != Status::invalid_input &&
                         p_ab.status != Status::invalid_input && c_ab.status != Status::invalid_input,
                     "valid input called invalid");
  }
  // How far from the world origin the shapes reach (a polyhedron sits at its
  // offset in its own frame): the world witness points round at that scale.
  auto reach = [](const Shape& s, const Pose& pose) {
    double offset = 0.0;
    if (const auto* poly = std::get_if<hedra::collision::Polyhedron>(&s)) offset = poly->hull->offset().norm();
    return pose.translation.norm() + offset + bounding_radius(s);
  };
  // A halfspace under B: a margin from a byte after all of the above.
  const std::uint8_t halfspace_margin = in.byte();
  check_halfspace(b, pose_a, pose_b, halfspace_margin % 4 == 1 ? 0.01 * (1 + halfspace_margin / 4) : 0.0,
                  validate(b).ok());
  check_raycast(b, pose_b, motion, reach(b, pose_b));
  check_casts(a, pose_a, b, pose_b, motion, valid, larger, std::max(reach(a, pose_a), reach(b, pose_b)));
  if (!valid) {
    check_geometry(d_ab, 0.0, "distance(a,b)");
    check_geometry(p_ab, 0.0, "penetration(a,b)");
    return 0;
  }

  const double size_scale = std::max(bounding_radius(a), bounding_radius(b));
  const double coordinates = std::max(reach(a, pose_a), reach(b, pose_b));
  const double tol = 1e-9 * size_scale + 64.0 * std::numeric_limits<double>::epsilon() * coordinates;

  check_geometry(d_ab, tol, "distance(a,b)");
  check_geometry(d_ba, tol, "distance(b,a)");
  check_geometry(p_ab, tol, "penetration(a,b)");
  check_geometry(p_ba, tol, "penetration(b,a)");

  if (d_ab.status == Status::ok && d_ba.status == Status::ok) {
    HEDRA_FUZZ_CHECK(d_ab.distance >= 0.0, "negative distance %.17g", d_ab.distance);
    HEDRA_FUZZ_CHECK(std::fabs(d_ab.distance - d_ba.distance) <= tol + d_ab.error_bound + d_ba.error_bound,
                     "distance not symmetric: %.17g vs %.17g (tol %.3g)", d_ab.distance, d_ba.distance, tol);
  }
  if (p_ab.status == Status::ok && p_ba.status == Status::ok) {
    HEDRA_FUZZ_CHECK(std::fabs(p_ab.distance - p_ba.distance) <= tol + p_ab.error_bound + p_ba.error_bound,
                     "signed distance not symmetric: %.17g vs %.17g (tol %.3g, bounds %.3g %.3g)", p_ab.distance,
                     p_ba.distance, tol, p_ab.error_bound, p_ba.error_bound);
  }
  if (i_ab.status == Status::ok && d_ab.status == Status::ok && d_ab.distance > tol + d_ab.error_bound) {
    HEDRA_FUZZ_CHECK(!i_ab.intersecting, "intersect says overlapping at distance %.17g", d_ab.distance);
  }
  if (i_ab.status == Status::ok && p_ab.status == Status::ok && p_ab.distance < -(tol + p_ab.error_bound)) {
    HEDRA_FUZZ_CHECK(i_ab.intersecting, "intersect says separated at depth %.17g", -p_ab.distance);
  }
  if (d_ab.status == Status::ok && p_ab.status == Status::ok && d_ab.distance > tol + d_ab.error_bound) {
    HEDRA_FUZZ_CHECK(std::fabs(d_ab.distance - p_ab.distance) <= tol + d_ab.error_bound + p_ab.error_bound,
                     "distance %.17g but penetration %.17g", d_ab.distance, p_ab.distance);
  }
  if (c_ab.status == Status::ok && p_ab.status == Status::ok) {
    // The manifold answers along its chosen axis (a face preferred within
    // the bias of manifold.hpp) and from clipped points, so its distance
    // is the exact one only within that bias; its verdict must agree away
    // from it, and a separation it reports is SAT's lower bound.
    const hedra::collision::ContactSettings settings;
    const double slack = tol + p_ab.error_bound;
    const double bias = settings.relative_bias * std::fabs(p_ab.distance) + settings.absolute_bias * 2.0 * size_scale;
    if (!c_ab.intersecting)
      HEDRA_FUZZ_CHECK(c_ab.distance <= p_ab.distance + bias + slack,
                       "contact separation %.17g above the signed distance %.17g", c_ab.distance, p_ab.distance);
    if (p_ab.distance < -(bias + slack))
      HEDRA_FUZZ_CHECK(c_ab.intersecting, "contact says apart at depth %.17g (contact distance %.17g)", -p_ab.distance,
                       c_ab.distance);
  }
  check_cached_frames(a, pose_a, b, pose_b, motion, tol, size_scale);
  if (std::holds_alternative<hedra::collision::Box>(a) && std::holds_alternative<hedra::collision::Box>(b))
    check_box_pair(a, pose_a, b, pose_b, c_ab, tol);
  if (std::holds_alternative<hedra::collision::Box>(a) && std::holds_alternative<hedra::collision::Box>(b))
    check_box_depth(a, pose_a, b, pose_b, p_ab, tol);
  return 0;
}
