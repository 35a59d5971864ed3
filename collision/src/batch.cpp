// Batch queries (batch.hpp): every row is the single query on that row, run
// in parallel_for's fixed chunks and written into the caller's array.
#include <hedra/collision/batch.hpp>

namespace hedra::collision {
namespace {

bool span_fits(PoseSpan span, std::size_t count) {
  return (span.size == 1 || span.size == count) && (span.data != nullptr || span.size == 0);
}

// Rows of a pair query; a span that does not fit makes every row invalid_input.
template <class Result, class Query>
void run_rows(PoseSpan poses_a, PoseSpan poses_b, std::size_t count, Result* out, const ParallelSettings& parallel,
              const Query& query) {
  if (count == 0) return;
  if (!span_fits(poses_a, count) || !span_fits(poses_b, count)) {
    for (std::size_t i = 0; i < count; ++i) {
      out[i] = Result{};
      out[i].status = Status::invalid_input;
    }
    return;
  }
  parallel_for(count, parallel, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) out[i] = query(poses_a[i], poses_b[i]);
  });
}

}  // namespace

void intersect_many(const Shape& a, PoseSpan poses_a, const Shape& b, PoseSpan poses_b, std::size_t count,
                    IntersectResult* out, const ParallelSettings& parallel, const GjkSettings& settings) {
  run_rows(poses_a, poses_b, count, out, parallel,
           [&](const Pose& pa, const Pose& pb) { return intersect(a, pa, b, pb, nullptr, settings); });
}

void distance_many(const Shape& a, PoseSpan poses_a, const Shape& b, PoseSpan poses_b, std::size_t count,
                   DistanceResult* out, const ParallelSettings& parallel, const GjkSettings& settings) {
  run_rows(poses_a, poses_b, count, out, parallel,
           [&](const Pose& pa, const Pose& pb) { return distance(a, pa, b, pb, nullptr, settings); });
}

void penetration_many(const Shape& a, PoseSpan poses_a, const Shape& b, PoseSpan poses_b, std::size_t count,
                      PenetrationResult* out, const ParallelSettings& parallel, const PenetrationSettings& settings) {
  run_rows(poses_a, poses_b, count, out, parallel,
           [&](const Pose& pa, const Pose& pb) { return penetration(a, pa, b, pb, nullptr, settings); });
}

void contact_many(const Shape& a, PoseSpan poses_a, const Shape& b, PoseSpan poses_b, std::size_t count,
                  ContactResult* out, const ParallelSettings& parallel, const ContactSettings& settings) {
  run_rows(poses_a, poses_b, count, out, parallel,
           [&](const Pose& pa, const Pose& pb) { return contact(a, pa, b, pb, nullptr, settings); });
}

void raycast_many(const Shape& shape, const Pose& pose, const Eigen::Vector3d* origins,
                  const Eigen::Vector3d* directions, std::size_t count, double max_fraction, RaycastResult* out,
                  const ParallelSettings& parallel, const RaycastSettings& settings) {
  if (count == 0) return;
  if (origins == nullptr || directions == nullptr) {
    for (std::size_t i = 0; i < count; ++i) {
      out[i] = RaycastResult{};
      out[i].status = CastStatus::invalid_input;
    }
    return;
  }
  parallel_for(count, parallel, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      out[i] = raycast(shape, pose, origins[i], directions[i], max_fraction, settings);
  });
}

}  // namespace hedra::collision
