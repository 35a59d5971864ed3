// Used only while the library has no batch queries (collision/batch.hpp):
// the same names and signatures, each row the single query, rows split in
// fixed chunks of kChunk whatever the thread count, chunks handed to
// std::threads started per call. Every row is written by exactly one call of
// the single query, so the bits never depend on the thread count.
#pragma once

#include <algorithm>
#include <atomic>
#include <hedra/collision/manifold.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/raycast.hpp>
#include <thread>
#include <vector>

namespace hedra::python::fallback {

using collision::Pose;
using collision::Shape;

struct ParallelSettings {
  int threads = 0;  // 0: all cores
};

struct PoseSpan {
  const Pose* data = nullptr;
  std::size_t size = 0;
  const Pose& operator[](std::size_t i) const { return data[size == 1 ? 0 : i]; }
};

constexpr std::size_t kChunk = 64;

template <class Body>
void parallel_for(std::size_t count, const ParallelSettings& parallel, Body&& body) {
  const std::size_t chunks = (count + kChunk - 1) / kChunk;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t workers =
      std::min<std::size_t>(chunks, parallel.threads > 0 ? static_cast<std::size_t>(parallel.threads) : cores);
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t c; (c = next.fetch_add(1)) < chunks;) body(c * kChunk, std::min(count, (c + 1) * kChunk));
  };
  if (workers <= 1) return work();
  std::vector<std::thread> pool;
  for (std::size_t w = 1; w < workers; ++w) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
}

template <class Result, class Query>
void rows(PoseSpan a, PoseSpan b, std::size_t count, Result* out, const ParallelSettings& parallel, Query query) {
  if ((a.size != 1 && a.size != count) || (b.size != 1 && b.size != count)) {
    for (std::size_t i = 0; i < count; ++i) out[i] = Result{}, out[i].status = collision::Status::invalid_input;
    return;
  }
  parallel_for(count, parallel, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) out[i] = query(a[i], b[i]);
  });
}

inline void intersect_many(const Shape& sa, PoseSpan a, const Shape& sb, PoseSpan b, std::size_t count,
                           collision::IntersectResult* out, const ParallelSettings& parallel,
                           const collision::GjkSettings& settings) {
  rows(a, b, count, out, parallel,
       [&](const Pose& pa, const Pose& pb) { return collision::intersect(sa, pa, sb, pb, nullptr, settings); });
}
inline void distance_many(const Shape& sa, PoseSpan a, const Shape& sb, PoseSpan b, std::size_t count,
                          collision::DistanceResult* out, const ParallelSettings& parallel,
                          const collision::GjkSettings& settings) {
  rows(a, b, count, out, parallel,
       [&](const Pose& pa, const Pose& pb) { return collision::distance(sa, pa, sb, pb, nullptr, settings); });
}
inline void penetration_many(const Shape& sa, PoseSpan a, const Shape& sb, PoseSpan b, std::size_t count,
                             collision::PenetrationResult* out, const ParallelSettings& parallel,
                             const collision::PenetrationSettings& settings) {
  rows(a, b, count, out, parallel,
       [&](const Pose& pa, const Pose& pb) { return collision::penetration(sa, pa, sb, pb, nullptr, settings); });
}
inline void contact_many(const Shape& sa, PoseSpan a, const Shape& sb, PoseSpan b, std::size_t count,
                         collision::ContactResult* out, const ParallelSettings& parallel,
                         const collision::ContactSettings& settings) {
  rows(a, b, count, out, parallel,
       [&](const Pose& pa, const Pose& pb) { return collision::contact(sa, pa, sb, pb, nullptr, settings); });
}
inline void raycast_many(const Shape& shape, const Pose& pose, const Eigen::Vector3d* origins,
                         const Eigen::Vector3d* directions, std::size_t count, double max_fraction,
                         collision::RaycastResult* out, const ParallelSettings& parallel,
                         const collision::RaycastSettings& settings) {
  parallel_for(count, parallel, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      out[i] = collision::raycast(shape, pose, origins[i], directions[i], max_fraction, settings);
  });
}

}  // namespace hedra::python::fallback
