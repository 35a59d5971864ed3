// Ray casts against one posed shape, margin included.
//
//   raycast(shape, pose, origin, direction, max_fraction, settings)
//
// The ray is origin + t direction, t in [0, max_fraction] (direction need not
// be unit: t is a fraction of it). The ray goes into the shape's local frame
// once (relative to the core's offset: a polyhedron's centroid), so a shape
// far from the world origin loses nothing of its own size. Then:
//   sphere, capsule (any margin), box and cylinder without margin: closed
//     forms (the closest approach to the centre or axis, then the root; the
//     slab test; the cylinder's slab and side);
//   everything else: the GJK ray cast of gjk_raycast.hpp on the core, grown
//     by the core's radius, which never steps past the surface. One that
//     stalls (or hits the cap) before its first clip has certified nothing
//     of the origin: penetration() of the origin settles it (inside, or
//     outside with a direction that starts one more ray cast).
// A ray starting inside (or within the tolerance of) the shape hits at 0 with
// started_inside and no normal. The tolerance is settings.tolerance times the
// shape's size, and never below the rounding of the ray's coordinates.
// invalid_input: the shape fails validate(), the pose is not valid(), the
// origin or direction is not finite (or beyond max_coordinate), the
// direction is zero, or max_fraction is negative or not finite.
#pragma once

#include <Eigen/Core>
#include <hedra/collision/cast_result.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/shapes.hpp>

namespace hedra::collision {

struct RaycastSettings {
  // A hit is reported once the ray's point is within tolerance * size of the
  // shape (size: the shape's bounding radius).
  double tolerance = 1e-10;
  // Iterations of the GJK ray cast (curved cores converge linearly: tens).
  int max_iterations = 128;
};

struct RaycastResult {
  // hit, separated (missed), initially_overlapping (started inside),
  // max_iterations or stalled (`fraction` safe, no verdict), degenerate,
  // invalid_input.
  CastStatus status = CastStatus::separated;
  bool hit = false;             // status is hit or initially_overlapping
  bool started_inside = false;  // status is initially_overlapping
  // hit: the ray's first point on the shape (never past it beyond the
  // tolerance); started inside: 0; missed: max_fraction; the cap or a stall:
  // the largest fraction known to be free of the shape.
  double fraction = 0.0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // origin + fraction * direction (world); zero on a miss
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // outward unit normal at the hit (world); zero otherwise
  // The point at `fraction` lies within error_bound of the shape's surface
  // (a bound on the distance, not on the fraction: a grazing ray may come
  // that close and miss).
  double error_bound = 0.0;
  int iterations = 0;  // GJK ray cast iterations (0 for closed forms)
};

RaycastResult raycast(const Shape& shape, const Pose& pose, const Eigen::Vector3d& origin,
                      const Eigen::Vector3d& direction, double max_fraction = 1.0,
                      const RaycastSettings& settings = {});

}  // namespace hedra::collision
