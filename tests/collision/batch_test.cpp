// Batch queries (batch.hpp) and parallel_for (parallel.hpp): every row equals
// the single query bit for bit with 1, 2, 4 and all threads, with an
// embedder's runner (serial in reverse, or one std::thread per task), with
// broadcast poses and count 0; mismatched spans make every row
// invalid_input; a batch allocates nothing; the chunks cover the range once
// and depend on the count only. Fixed seeds.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <atomic>
#include <cstring>
#include <hedra/collision/batch.hpp>
#include <mutex>
#include <random>
#include <thread>
#include <vector>

#include "allocation_counter.hpp"

namespace hedra::collision {
namespace {

using Vec = Eigen::Vector3d;

bool same_bits(double x, double y) { return std::memcmp(&x, &y, sizeof(double)) == 0; }
bool same_bits(const Vec& x, const Vec& y) { return std::memcmp(x.data(), y.data(), 3 * sizeof(double)) == 0; }

bool same(const IntersectResult& x, const IntersectResult& y) {
  return x.status == y.status && x.intersecting == y.intersecting && x.iterations == y.iterations &&
         x.support_calls == y.support_calls;
}
bool same(const DistanceResult& x, const DistanceResult& y) {
  return x.status == y.status && x.intersecting == y.intersecting && same_bits(x.distance, y.distance) &&
         same_bits(x.normal, y.normal) && same_bits(x.point_a, y.point_a) && same_bits(x.point_b, y.point_b) &&
         same_bits(x.error_bound, y.error_bound) && x.iterations == y.iterations && x.support_calls == y.support_calls;
}
bool same(const PenetrationResult& x, const PenetrationResult& y) {
  return x.status == y.status && x.intersecting == y.intersecting && same_bits(x.distance, y.distance) &&
         same_bits(x.normal, y.normal) && same_bits(x.point_a, y.point_a) && same_bits(x.point_b, y.point_b) &&
         same_bits(x.error_bound, y.error_bound) && x.gjk_iterations == y.gjk_iterations &&
         x.epa_iterations == y.epa_iterations && x.support_calls == y.support_calls;
}
bool same(const ContactResult& x, const ContactResult& y) {
  if (!(x.status == y.status && x.intersecting == y.intersecting && same_bits(x.distance, y.distance) &&
        same_bits(x.normal, y.normal) && same_bits(x.point_a, y.point_a) && same_bits(x.point_b, y.point_b) &&
        x.count == y.count && x.path == y.path))
    return false;
  for (int k = 0; k < x.count; ++k)
    if (!same_bits(x.points[k].point, y.points[k].point) || !same_bits(x.points[k].depth, y.points[k].depth) ||
        x.points[k].id != y.points[k].id)
      return false;
  return true;
}
bool same(const RaycastResult& x, const RaycastResult& y) {
  return x.status == y.status && x.hit == y.hit && same_bits(x.fraction, y.fraction) && same_bits(x.point, y.point) &&
         same_bits(x.normal, y.normal) && same_bits(x.error_bound, y.error_bound) && x.iterations == y.iterations;
}

// An embedder's runner that runs the tasks one after another, last first.
class ReverseSerialRunner final : public TaskRunner {
 public:
  int concurrency() const override { return 3; }
  void run(std::size_t n, void (*task)(std::size_t, void*), void* context) override {
    for (std::size_t i = n; i-- > 0;) task(i, context);
  }
};
// An embedder's runner that starts one std::thread per task.
class ThreadPerTaskRunner final : public TaskRunner {
 public:
  int concurrency() const override { return 5; }
  void run(std::size_t n, void (*task)(std::size_t, void*), void* context) override {
    std::vector<std::thread> threads;
    for (std::size_t i = 0; i < n; ++i) threads.emplace_back([=] { task(i, context); });
    for (std::thread& t : threads) t.join();
  }
};

std::vector<ParallelSettings> all_settings() {
  static ReverseSerialRunner reverse;
  static ThreadPerTaskRunner per_task;
  return {{1, nullptr}, {2, nullptr}, {4, nullptr}, {0, nullptr}, {0, &reverse}, {0, &per_task}};
}

std::vector<Shape> test_shapes() {
  std::mt19937_64 rng(3011);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec> points;
  for (int i = 0; i < 24; ++i) points.emplace_back(0.6 * u(rng), 0.4 * u(rng), 0.5 * u(rng));
  const ConvexPolyhedron::BuildResult hull = ConvexPolyhedron::build(points);
  EXPECT_TRUE(hull.ok());
  return {Box{Vec(0.5, 0.3, 0.2), 0.0},
          Polyhedron{hull.polyhedron, 0.0},
          Capsule{0.2, 0.4, 0.0},
          Cylinder{0.3, 0.4, 0.02},
          Cone{0.3, 0.5, 0.0},
          Sphere{0.4, 0.0},
          Polyhedron{hull.polyhedron, 0.05}};
}

std::vector<Pose> random_poses(std::mt19937_64& rng, std::size_t n, double spread) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Pose> poses;
  for (std::size_t i = 0; i < n; ++i)
    poses.push_back(Pose::from_quaternion(Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)),
                                          spread * Vec(u(rng), u(rng), u(rng))));
  return poses;
}

// Every row of every batch against the single query, for every runner and
// thread count, with N poses on both sides and broadcast on either.
TEST(Batch, RowsEqualTheSingleQueryBitForBitForEveryThreadCount) {
  const std::vector<Shape> shapes = test_shapes();
  std::mt19937_64 rng(3012);
  constexpr std::size_t n = 700;  // more than kMaxParallelChunks: chunks of two rows and one
  int overlapping = 0, separated = 0;
  for (std::size_t s = 0; s < shapes.size(); ++s) {
    const Shape& a = shapes[s];
    const Shape& b = shapes[(s * 3 + 1) % shapes.size()];
    const std::vector<Pose> pa = random_poses(rng, n, 0.9), pb = random_poses(rng, n, 0.9);
    for (const auto& spans : {std::pair<PoseSpan, PoseSpan>{{pa.data(), n}, {pb.data(), n}},
                              std::pair<PoseSpan, PoseSpan>{{pa.data(), 1}, {pb.data(), n}},
                              std::pair<PoseSpan, PoseSpan>{{pa.data(), n}, {pb.data(), 1}}}) {
      const PoseSpan A = spans.first, B = spans.second;
      std::vector<IntersectResult> ri(n);
      std::vector<DistanceResult> rd(n);
      std::vector<PenetrationResult> rp(n);
      std::vector<ContactResult> rc(n);
      ContactSettings cs;
      cs.contact_distance = 0.05;
      for (const ParallelSettings& p : all_settings()) {
        intersect_many(a, A, b, B, n, ri.data(), p);
        distance_many(a, A, b, B, n, rd.data(), p);
        penetration_many(a, A, b, B, n, rp.data(), p);
        contact_many(a, A, b, B, n, rc.data(), p, cs);
        for (std::size_t i = 0; i < n; ++i) {
          ASSERT_TRUE(same(ri[i], intersect(a, A[i], b, B[i]))) << "row " << i << " threads " << p.threads;
          ASSERT_TRUE(same(rd[i], distance(a, A[i], b, B[i]))) << "row " << i << " threads " << p.threads;
          ASSERT_TRUE(same(rp[i], penetration(a, A[i], b, B[i]))) << "row " << i << " threads " << p.threads;
          ASSERT_TRUE(same(rc[i], contact(a, A[i], b, B[i], nullptr, cs))) << "row " << i << " threads " << p.threads;
        }
      }
      for (std::size_t i = 0; i < n; ++i) (rp[i].intersecting ? overlapping : separated)++;
    }
  }
  // Both answers occur, so the rows compare more than one path.
  EXPECT_GT(overlapping, 1000);
  EXPECT_GT(separated, 1000);
}

TEST(Batch, RaycastRowsEqualTheSingleRayForEveryThreadCount) {
  const std::vector<Shape> shapes = test_shapes();
  std::mt19937_64 rng(3013);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  constexpr std::size_t n = 600;
  std::vector<Vec> origins, directions;
  for (std::size_t i = 0; i < n; ++i) {
    origins.emplace_back(2.0 * u(rng), 2.0 * u(rng), 2.0 * u(rng));
    directions.push_back(-origins.back() + 0.5 * Vec(u(rng), u(rng), u(rng)));
  }
  int hits = 0;
  for (const Shape& shape : shapes) {
    const Pose pose = random_poses(rng, 1, 0.2)[0];
    std::vector<RaycastResult> out(n);
    for (const ParallelSettings& p : all_settings()) {
      raycast_many(shape, pose, origins.data(), directions.data(), n, 1.5, out.data(), p);
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_TRUE(same(out[i], raycast(shape, pose, origins[i], directions[i], 1.5))) << "ray " << i;
    }
    for (const RaycastResult& r : out) hits += r.hit;
  }
  EXPECT_GT(hits, 500);
}

TEST(Batch, CountZeroWritesNothingAndMismatchedSpansAreInvalidInput) {
  const std::vector<Shape> shapes = test_shapes();
  std::mt19937_64 rng(3014);
  const std::vector<Pose> poses = random_poses(rng, 5, 1.0);
  PenetrationResult untouched;
  untouched.distance = 42.0;
  penetration_many(shapes[0], {poses.data(), 5}, shapes[1], {poses.data(), 5}, 0, &untouched);
  penetration_many(shapes[0], {nullptr, 0}, shapes[1], {nullptr, 0}, 0, &untouched);
  EXPECT_EQ(untouched.distance, 42.0);
  std::vector<PenetrationResult> out(4);
  penetration_many(shapes[0], {poses.data(), 5}, shapes[1], {poses.data(), 4}, 4, out.data());  // 5 is neither 1 nor 4
  for (const PenetrationResult& r : out) EXPECT_EQ(r.status, Status::invalid_input);
  std::vector<ContactResult> contacts(3);
  contact_many(shapes[0], {poses.data(), 1}, shapes[1], {nullptr, 3}, 3, contacts.data());
  for (const ContactResult& r : contacts) EXPECT_EQ(r.status, Status::invalid_input);
  // A bad pose in one row is that row's invalid_input only.
  std::vector<Pose> bad = poses;
  bad[2].translation.x() = std::numeric_limits<double>::quiet_NaN();
  std::vector<DistanceResult> d(5);
  distance_many(shapes[0], {bad.data(), 5}, shapes[1], {poses.data(), 1}, 5, d.data(), {2, nullptr});
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(d[i].status == Status::invalid_input, i == 2) << i;
}

TEST(Batch, AllocatesNothingPerQueryOnThePool) {
  const std::vector<Shape> shapes = test_shapes();
  std::mt19937_64 rng(3015);
  constexpr std::size_t n = 300;
  const std::vector<Pose> pa = random_poses(rng, n, 0.8), pb = random_poses(rng, n, 0.8);
  std::vector<PenetrationResult> rp(n);
  std::vector<ContactResult> rc(n);
  // Warm up: the pool's threads and the shared box topology are built once.
  penetration_many(shapes[0], {pa.data(), n}, shapes[1], {pb.data(), n}, n, rp.data(), {0, nullptr});
  contact_many(shapes[0], {pa.data(), n}, shapes[0], {pb.data(), n}, n, rc.data(), {0, nullptr});
  const long before = g_allocations.load();
  for (int t : {1, 2, 0}) {
    penetration_many(shapes[0], {pa.data(), n}, shapes[1], {pb.data(), n}, n, rp.data(), {t, nullptr});
    contact_many(shapes[0], {pa.data(), n}, shapes[0], {pb.data(), n}, n, rc.data(), {t, nullptr});
  }
  EXPECT_EQ(g_allocations.load(), before);
}

// The chunks cover [0, count) exactly once, in ranges that depend on the
// count only (the same ranges for every thread count and runner).
TEST(ParallelFor, ChunksCoverTheRangeOnceAndDependOnTheCountOnly) {
  for (std::size_t count : {0u, 1u, 2u, 7u, 511u, 512u, 513u, 10000u, 123457u}) {
    std::vector<std::vector<std::pair<std::size_t, std::size_t>>> seen;
    for (const ParallelSettings& p : all_settings()) {
      std::vector<std::atomic<int>> hits(count);
      std::vector<std::pair<std::size_t, std::size_t>> ranges(parallel_chunk_count(count));
      parallel_for_chunks(count, p, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
        ranges[chunk] = {begin, end};
        for (std::size_t i = begin; i < end; ++i) hits[i]++;
      });
      for (std::size_t i = 0; i < count; ++i) ASSERT_EQ(hits[i].load(), 1) << count << " " << i;
      seen.push_back(ranges);
    }
    for (const auto& r : seen) EXPECT_EQ(r, seen.front()) << count;
    EXPECT_LE(parallel_chunk_count(count), kMaxParallelChunks);
  }
}

// A parallel_for inside a pool task, and parallel_fors from two threads at
// once, run (inline where the pool is busy) and complete every row.
TEST(ParallelFor, NestedAndConcurrentCallsComplete) {
  std::vector<std::atomic<int>> hits(64 * 100);
  parallel_for(64, {0, nullptr}, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      parallel_for(100, {0, nullptr}, [&, i](std::size_t b, std::size_t e) {
        for (std::size_t j = b; j < e; ++j) hits[i * 100 + j]++;
      });
  });
  for (const auto& h : hits) ASSERT_EQ(h.load(), 1);
  std::vector<std::atomic<int>> first(5000), second(5000);
  std::thread other([&] {
    for (int round = 0; round < 50; ++round)
      parallel_for(100, {0, nullptr}, [&](std::size_t b, std::size_t e) {
        for (std::size_t j = b; j < e; ++j) second[round * 100 + j]++;
      });
  });
  for (int round = 0; round < 50; ++round)
    parallel_for(100, {0, nullptr}, [&](std::size_t b, std::size_t e) {
      for (std::size_t j = b; j < e; ++j) first[round * 100 + j]++;
    });
  other.join();
  for (std::size_t i = 0; i < first.size(); ++i) ASSERT_TRUE(first[i] == 1 && second[i] == 1) << i;
}

TEST(ParallelFor, WorkersFollowTheSettings) {
  static ReverseSerialRunner reverse;
  EXPECT_EQ(parallel_workers({1, nullptr}), 1);
  EXPECT_EQ(parallel_workers({0, &reverse}), 3);
  EXPECT_EQ(parallel_workers({2, &reverse}), 2);
  EXPECT_EQ(parallel_workers({9, &reverse}), 3);
  EXPECT_GE(default_task_runner().concurrency(), 1);
  EXPECT_EQ(parallel_workers({0, nullptr}), default_task_runner().concurrency());
}

}  // namespace
}  // namespace hedra::collision
