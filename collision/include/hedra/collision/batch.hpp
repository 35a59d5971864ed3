// Batch queries: one shape pair (or one shape and many rays) at many poses,
// on all cores.
//
//   intersect_many / distance_many / penetration_many / contact_many
//       row i = the single query (query.hpp, manifold.hpp) of a at
//       poses_a[i] against b at poses_b[i], without a cache;
//   raycast_many: row i = raycast(shape, pose, origins[i], directions[i]).
//
// Exactness: each row is computed by exactly the code of the single query,
// with nothing shared between rows, so row i equals the single query bit for
// bit whatever the thread count or the runner (parallel.hpp). Rows are cut
// into parallel_for's fixed chunks, each row written once into the caller's
// array: no allocation, no reduction.
//
// A PoseSpan of size 1 is broadcast to every row. Sizes other than 1 or
// count (or a null pointer with a non-zero size) make every row
// invalid_input; count 0 writes nothing.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <hedra/collision/manifold.hpp>
#include <hedra/collision/parallel.hpp>
#include <hedra/collision/pose.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/raycast.hpp>
#include <hedra/collision/shapes.hpp>

namespace hedra::collision {

// N poses, or one pose broadcast to every row (size == 1).
struct PoseSpan {
  const Pose* data = nullptr;
  std::size_t size = 0;
  const Pose& operator[](std::size_t i) const { return data[size == 1 ? 0 : i]; }
};

// Row i of `out` (count rows, caller-allocated) equals the single query on row i, bit for bit,
// whatever the thread count. A PoseSpan's size is 1 or count (otherwise: every row invalid_input).
void intersect_many(const Shape& a, PoseSpan poses_a, const Shape& b, PoseSpan poses_b, std::size_t count,
                    IntersectResult* out, const ParallelSettings& parallel = {}, const GjkSettings& settings = {});
void distance_many(const Shape& a, PoseSpan poses_a, const Shape& b, PoseSpan poses_b, std::size_t count,
                   DistanceResult* out, const ParallelSettings& parallel = {}, const GjkSettings& settings = {});
void penetration_many(const Shape& a, PoseSpan poses_a, const Shape& b, PoseSpan poses_b, std::size_t count,
                      PenetrationResult* out, const ParallelSettings& parallel = {},
                      const PenetrationSettings& settings = {});
void contact_many(const Shape& a, PoseSpan poses_a, const Shape& b, PoseSpan poses_b, std::size_t count,
                  ContactResult* out, const ParallelSettings& parallel = {}, const ContactSettings& settings = {});
// Rays: one shape at one pose, count rays (origins[i] + t directions[i], t in [0, max_fraction]).
void raycast_many(const Shape& shape, const Pose& pose, const Eigen::Vector3d* origins,
                  const Eigen::Vector3d* directions, std::size_t count, double max_fraction, RaycastResult* out,
                  const ParallelSettings& parallel = {}, const RaycastSettings& settings = {});

}  // namespace hedra::collision
