// Thread safety of the queries on shared shapes: hulls are immutable and
// shared through std::shared_ptr<const ConvexPolyhedron>, per-query state
// lives on the stack or in the caller's cache. Four std::threads run the same
// distance() and penetration() queries (each with its own cache) over the
// same shared hulls, and every result must equal the single-threaded one bit
// for bit. Fixed seed.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstring>
#include <hedra/collision/query.hpp>
#include <random>
#include <thread>
#include <vector>

namespace hedra::collision {
namespace {

using Vec = Eigen::Vector3d;

struct Answer {
  DistanceResult distance;
  PenetrationResult penetration;
};

bool same_bits(const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
  return std::memcmp(x.data(), y.data(), 3 * sizeof(double)) == 0;
}
bool same_bits(double x, double y) { return std::memcmp(&x, &y, sizeof(double)) == 0; }

bool same(const Answer& x, const Answer& y) {
  const DistanceResult &a = x.distance, &b = y.distance;
  const PenetrationResult &p = x.penetration, &q = y.penetration;
  return a.status == b.status && a.intersecting == b.intersecting && same_bits(a.distance, b.distance) &&
         same_bits(a.normal, b.normal) && same_bits(a.point_a, b.point_a) && same_bits(a.point_b, b.point_b) &&
         same_bits(a.error_bound, b.error_bound) && a.iterations == b.iterations && p.status == q.status &&
         p.intersecting == q.intersecting && same_bits(p.distance, q.distance) && same_bits(p.normal, q.normal) &&
         same_bits(p.point_a, q.point_a) && same_bits(p.point_b, q.point_b) &&
         same_bits(p.error_bound, q.error_bound) && p.gjk_iterations == q.gjk_iterations &&
         p.epa_iterations == q.epa_iterations;
}

TEST(ThreadSafety, SharedHullsGiveBitIdenticalAnswersFromFourThreads) {
  std::mt19937_64 rng(401);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<std::shared_ptr<const ConvexPolyhedron>> hulls;
  for (int n : {12, 40, 200, 2000}) {  // both sides of the hill-climbing crossover
    std::vector<Vec> points;
    for (int i = 0; i < n; ++i) points.emplace_back(u(rng), 0.7 * u(rng), 0.5 * u(rng));
    const ConvexPolyhedron::BuildResult built = ConvexPolyhedron::build(points);
    ASSERT_TRUE(built.ok()) << built.message;
    hulls.push_back(built.polyhedron);
  }
  struct Query {
    Shape a, b;
    Pose pa, pb;
  };
  std::vector<Query> queries;
  for (int i = 0; i < 400; ++i) {
    const auto& ha = hulls[i % hulls.size()];
    const auto& hb = hulls[(i / hulls.size()) % hulls.size()];
    const Shape b = i % 5 == 0 ? Shape(Cylinder{0.4, 0.6, 0.0}) : Shape(Polyhedron{hb, i % 3 == 0 ? 0.05 : 0.0});
    const Eigen::Quaterniond qa(g(rng), g(rng), g(rng), g(rng)), qb(g(rng), g(rng), g(rng), g(rng));
    queries.push_back({Polyhedron{ha, 0.0}, b, Pose::from_quaternion(qa, 1.5 * Vec(u(rng), u(rng), u(rng))),
                       Pose::from_quaternion(qb, 1.5 * Vec(u(rng), u(rng), u(rng)))});
  }
  // Each worker keeps one cache for the whole sequence, as a caller would.
  auto run_all = [&queries](std::vector<Answer>& out) {
    GjkCache distance_cache, penetration_cache;
    out.resize(queries.size());
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const Query& q = queries[i];
      out[i].distance = distance(q.a, q.pa, q.b, q.pb, &distance_cache);
      out[i].penetration = penetration(q.a, q.pa, q.b, q.pb, &penetration_cache);
    }
  };
  std::vector<Answer> expected;
  run_all(expected);
  int separated = 0, overlapping = 0;
  for (const Answer& a : expected) (a.penetration.distance > 0.0 ? separated : overlapping)++;
  EXPECT_GT(separated, 50);  // the sample exercises GJK alone and GJK + EPA
  EXPECT_GT(overlapping, 50);

  constexpr int kThreads = 4;
  for (int round = 0; round < 5; ++round) {
    std::vector<std::vector<Answer>> got(kThreads);
    std::vector<std::thread> workers;
    for (int t = 0; t < kThreads; ++t) workers.emplace_back(run_all, std::ref(got[t]));
    for (std::thread& w : workers) w.join();
    for (int t = 0; t < kThreads; ++t) {
      ASSERT_EQ(got[t].size(), expected.size());
      for (std::size_t i = 0; i < expected.size(); ++i)
        ASSERT_TRUE(same(got[t][i], expected[i])) << "round " << round << " thread " << t << " query " << i;
    }
  }
}

}  // namespace
}  // namespace hedra::collision
