// Contact-manifold queries: hedra's contact() against Bullet 3.24's
// polyhedral path (btPolyhedralContactClipping::findSeparatingAxis +
// clipHullAgainstHull, as btConvexConvexAlgorithm runs it), on the same
// pairs in one run.
//
// Families (fixed seeds, generated once, outside the timed loops; 64 pairs
// each, every pair overlapping unless said otherwise):
//   box_resting   a 0.5-box resting on a 1-box, turned about z, 1 cm deep:
//                 face contact, four points
//   box_random    two unit boxes in random orientations, overlapping
//   hull8, hull32, hull128
//                 two hulls of points on an ellipsoid (every point a vertex)
//                 in random orientations, overlapping
//   box_separated, hull32_separated
//                 boxes 0.1 apart, 32-vertex hulls apart (contact() with and
//                 without a per-pair ContactCache: the cached separating
//                 face axis answers alone)
// Each benchmark loops over its family's pairs, one query per iteration
// (time per iteration = time per query). Bullet's objects (shapes with their
// polyhedral features, transforms, clipping buffers) are built once per pair
// outside the loop. Bullet's clipping reports every clipped point (it reduces
// them later in btPersistentManifold); hedra's answer includes the reduction
// to at most four points.
//
// Variants: hedra (the default axis search), hedra_sat and
// hedra_exact_normal (ContactSettings::axis_search forced), penetration
// (penetration() on the same pairs: contact()'s yardstick).
//
// Counter `points`: mean number of contact points per query.
//
// Run: build/bin/contact_benchmark --benchmark_repetitions=5
//      --benchmark_report_aggregates_only=true (read the medians).
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <hedra/collision/manifold.hpp>
#include <memory>
#include <random>
#include <string>
#include <vector>
#ifdef HEDRA_WITH_PEERS
#  include "bullet_manifold.hpp"
#endif

namespace {

using namespace hedra::collision;
using Vec = Eigen::Vector3d;

struct Pair {
  Shape a;
  Pose pose_a;
  Shape b;
  Pose pose_b;
};

struct Family {
  std::string name;
  std::vector<Pair> pairs;
};

Vec random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Vec(g(rng), g(rng), g(rng)).normalized();
}

std::shared_ptr<const ConvexPolyhedron> ellipsoid_hull(std::mt19937_64& rng, int n, const Vec& radii) {
  std::vector<Vec> points;
  for (int i = 0; i < n; ++i) points.push_back(random_unit(rng).cwiseProduct(radii));
  return ConvexPolyhedron::build(points).polyhedron;
}

Pose random_pose(std::mt19937_64& rng, const Vec& t) {
  Eigen::Quaterniond q(Eigen::Vector4d(random_unit(rng).x(), random_unit(rng).y(), random_unit(rng).z(), 1.0));
  return Pose::from_quaternion(q, t);
}

std::vector<Family> make_families() {
  std::mt19937_64 rng(424242);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Family> out;
  Family resting{"box_resting", {}};
  for (int i = 0; i < 64; ++i)
    resting.pairs.push_back({Box{{1, 1, 1}}, Pose::identity(), Box{{0.5, 0.5, 0.5}},
                             Pose::from_quaternion(Eigen::Quaterniond(Eigen::AngleAxisd(3.0 * u(rng), Vec::UnitZ())),
                                                   Vec(0.3 * u(rng), 0.3 * u(rng), 1.49))});
  out.push_back(resting);
  Family boxes{"box_random", {}};
  for (int i = 0; i < 64; ++i)
    boxes.pairs.push_back({Box{{0.5, 0.5, 0.5}}, random_pose(rng, Vec::Zero()), Box{{0.5, 0.5, 0.5}},
                           random_pose(rng, 0.9 * random_unit(rng))});
  out.push_back(boxes);
  for (const int n : {8, 32, 128}) {
    Family f{"hull" + std::to_string(n), {}};
    for (int i = 0; i < 64; ++i) {
      const auto ha = ellipsoid_hull(rng, n, Vec(1.0, 0.8, 0.6));
      const auto hb = ellipsoid_hull(rng, n, Vec(0.7, 0.9, 0.5));
      f.pairs.push_back(
          {Polyhedron{ha}, random_pose(rng, Vec::Zero()), Polyhedron{hb}, random_pose(rng, 0.5 * random_unit(rng))});
    }
    out.push_back(f);
  }
  Family hulls_apart{"hull32_separated", {}};
  for (int i = 0; i < 64; ++i) {
    const auto ha = ellipsoid_hull(rng, 32, Vec(1.0, 0.8, 0.6));
    const auto hb = ellipsoid_hull(rng, 32, Vec(0.7, 0.9, 0.5));
    hulls_apart.pairs.push_back(
        {Polyhedron{ha}, random_pose(rng, Vec::Zero()), Polyhedron{hb}, random_pose(rng, 2.2 * random_unit(rng))});
  }
  out.push_back(hulls_apart);
  Family separated{"box_separated", {}};
  for (int i = 0; i < 64; ++i)
    separated.pairs.push_back({Box{{1, 1, 1}}, Pose::identity(), Box{{0.5, 0.5, 0.5}},
                               Pose::from_quaternion(Eigen::Quaterniond(Eigen::AngleAxisd(3.0 * u(rng), Vec::UnitZ())),
                                                     Vec(0.3 * u(rng), 0.3 * u(rng), 1.6))});
  out.push_back(separated);
  return out;
}

void register_hedra(const Family& f, bool cached, const char* suffix = "",
                    PolytopeAxisSearch search = PolytopeAxisSearch::automatic) {
  ContactSettings settings;
  settings.axis_search = search;
  benchmark::RegisterBenchmark(("contact/" + f.name + (cached ? "/hedra_cached" : "/hedra") + suffix).c_str(),
                               [&f, cached, settings](benchmark::State& state) {
                                 std::vector<ContactCache> caches(f.pairs.size());
                                 std::size_t i = 0;
                                 long points = 0, queries = 0;
                                 for (auto _ : state) {
                                   const Pair& p = f.pairs[i];
                                   const ContactResult r =
                                       contact(p.a, p.pose_a, p.b, p.pose_b, cached ? &caches[i] : nullptr, settings);
                                   benchmark::DoNotOptimize(r);
                                   points += r.count;
                                   ++queries;
                                   i = i + 1 == f.pairs.size() ? 0 : i + 1;
                                 }
                                 state.counters["points"] = static_cast<double>(points) / std::max(queries, 1L);
                               });
}

// penetration() on the same pairs: the yardstick of contact()'s cost.
void register_penetration(const Family& f) {
  benchmark::RegisterBenchmark(("contact/" + f.name + "/penetration").c_str(), [&f](benchmark::State& state) {
    std::size_t i = 0;
    for (auto _ : state) {
      const Pair& p = f.pairs[i];
      benchmark::DoNotOptimize(penetration(p.a, p.pose_a, p.b, p.pose_b));
      i = i + 1 == f.pairs.size() ? 0 : i + 1;
    }
  });
}

#ifdef HEDRA_WITH_PEERS
void register_bullet(const Family& f, bool double_precision) {
  benchmark::RegisterBenchmark(
      ("contact/" + f.name + (double_precision ? "/bullet_f64_polyhedral" : "/bullet_f32_polyhedral")).c_str(),
      [&f, double_precision](benchmark::State& state) {
        std::vector<std::unique_ptr<hedra::peers::PreparedManifold>> prepared;
        for (const Pair& p : f.pairs)
          prepared.push_back(hedra::peers::prepare_bullet_manifold({p.a, p.pose_a, p.b, p.pose_b}, double_precision));
        hedra::peers::PeerManifold m;
        m.points.reserve(64);
        prepared[0]->query(0.0, m);
        if (!m.supported) {
          state.SkipWithError(m.status.c_str());
          return;
        }
        std::size_t i = 0;
        long points = 0, queries = 0;
        for (auto _ : state) {
          prepared[i]->query(0.0, m);
          benchmark::DoNotOptimize(m);
          points += m.total;
          ++queries;
          i = i + 1 == prepared.size() ? 0 : i + 1;
        }
        state.counters["points"] = static_cast<double>(points) / std::max(queries, 1L);
      });
}
#endif

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  static const std::vector<Family> families = make_families();
  for (const Family& f : families) {
    register_hedra(f, false);
    register_hedra(f, false, "_sat", PolytopeAxisSearch::sat);
    register_hedra(f, false, "_exact_normal", PolytopeAxisSearch::exact_normal);
    register_penetration(f);
    if (f.name.find("separated") != std::string::npos || f.name == "box_resting") register_hedra(f, true);
#ifdef HEDRA_WITH_PEERS
    register_bullet(f, true);
    register_bullet(f, false);
#endif
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
