// hedra's quickhull against qhull (libqhull_r, through tools/reference) on the
// same point sets, side by side in one run:
//   ball/N      uniform in the unit ball, N = 1e3, 1e5, 1e6
//   sphere/N    on the unit sphere (every point is a vertex), N = 1e4, 1e5
//   cube_grid/N a 100 x 100 integer grid on each face of a cube, shared edge
//               and corner points once (heavy coplanarity: 8 vertices)
// Every set is generated once, with a fixed seed, outside the timed loops.
//
// qhull options. hedra returns merged convex polygon faces, so the
// comparable qhull run is its default, "qhull" with no option: in 3D it
// pre-merges coplanar and non-convex facets ('C-0') and returns merged
// facets, the same work hedra does. "Qt" (the same build, then triangulated
// output) is timed too, since it is the usual way qhull is called for
// triangle meshes; neither run computes area or volume.
//
// Each benchmark reports counters, all computed once per set outside timing:
//   points            input size
//   vertices          hull vertices of this implementation
//   vertex_sets_equal 1 when hedra's vertex set (input indices) equals
//                     qhull's default-option vertex set, else 0
// hedra's builder is reused across iterations (and warmed up once), as an
// application building many hulls would. Run with repetitions and read
// medians: tools/microbench/hull_table.py turns --benchmark_format=json output into a
// table.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <hedra/hull/quickhull.hpp>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "qhull_reference.hpp"

namespace {

using Points = std::vector<Eigen::Vector3d>;

// Uniform doubles from mt19937_64's (standard-fixed) bit stream, so a seed
// gives the same set with any standard library.
double uniform(std::mt19937_64& engine, double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(engine() >> 11) * 0x1.0p-53);
}

Points uniform_ball(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  Points p;
  p.reserve(n);
  while (p.size() < n) {
    const Eigen::Vector3d q(uniform(engine, -1, 1), uniform(engine, -1, 1), uniform(engine, -1, 1));
    if (q.squaredNorm() <= 1.0) p.push_back(q);
  }
  return p;
}

Points sphere_surface(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  Points p;
  p.reserve(n);
  while (p.size() < n) {
    const Eigen::Vector3d q(uniform(engine, -1, 1), uniform(engine, -1, 1), uniform(engine, -1, 1));
    const double r2 = q.squaredNorm();
    if (r2 <= 1.0 && r2 > 1e-6) p.push_back(q / std::sqrt(r2));
  }
  return p;
}

// The surface of the cube [-(k-1), k-1]^3 sampled at every second integer:
// k x k points per face, points on shared edges and corners once.
Points cube_grid(int k, std::uint64_t seed) {
  Points p;
  const int h = k - 1;
  for (int x = -h; x <= h; x += 2) {
    for (int y = -h; y <= h; y += 2) {
      for (int z = -h; z <= h; z += 2) {
        if (std::abs(x) == h || std::abs(y) == h || std::abs(z) == h) p.emplace_back(x, y, z);
      }
    }
  }
  std::mt19937_64 engine(seed);  // shuffled: no help from a sorted order
  for (std::size_t i = p.size(); i > 1; --i) std::swap(p[i - 1], p[engine() % i]);
  return p;
}

struct PointSet {
  std::string name;
  std::function<Points()> make;
};

const std::vector<PointSet>& point_sets() {
  static const std::vector<PointSet> sets = {
      {"ball/1000", [] { return uniform_ball(1000, 1); }},
      {"ball/100000", [] { return uniform_ball(100000, 2); }},
      {"ball/1000000", [] { return uniform_ball(1000000, 3); }},
      {"sphere/10000", [] { return sphere_surface(10000, 4); }},
      {"sphere/100000", [] { return sphere_surface(100000, 5); }},
      {"cube_grid/100x100", [] { return cube_grid(100, 6); }},
  };
  return sets;
}

// Per set, computed once: the points and the vertex-set comparison.
struct Prepared {
  Points points;
  std::size_t hedra_vertices = 0;
  std::size_t qhull_vertices = 0;
  bool vertex_sets_equal = false;
};

const Prepared& prepared(const PointSet& set) {
  static std::map<std::string, Prepared> cache;
  auto it = cache.find(set.name);
  if (it != cache.end()) return it->second;
  Prepared p;
  p.points = set.make();
  const hedra::hull::QuickhullResult h = hedra::hull::build_hull(p.points);
  std::vector<int> hedra_set;
  for (hedra::hull::Index i : h.input_index) hedra_set.push_back(static_cast<int>(i));
  std::sort(hedra_set.begin(), hedra_set.end());
  const hedra::reference::QhullHull q = hedra::reference::qhull_hull(p.points, "");
  p.hedra_vertices = hedra_set.size();
  p.qhull_vertices = q.vertices.size();
  p.vertex_sets_equal = h.ok() && q.ok && hedra_set == q.vertices;
  if (!p.vertex_sets_equal) {
    std::fprintf(stderr, "%s: vertex sets differ (hedra %s, %zu vertices; qhull %s, %zu vertices)\n", set.name.c_str(),
                 hedra::hull::to_string(h.status), hedra_set.size(), q.ok ? "ok" : "failed", q.vertices.size());
  }
  return cache.emplace(set.name, std::move(p)).first->second;
}

void set_counters(benchmark::State& state, const Prepared& p, std::size_t vertices) {
  state.counters["points"] = static_cast<double>(p.points.size());
  state.counters["vertices"] = static_cast<double>(vertices);
  state.counters["vertex_sets_equal"] = p.vertex_sets_equal ? 1.0 : 0.0;
}

void bench_hedra(benchmark::State& state, const PointSet* set) {
  const Prepared& p = prepared(*set);
  static hedra::hull::QuickhullBuilder builder;  // reused across iterations and repetitions
  builder.build(p.points);                       // warm-up, untimed
  std::size_t vertices = 0;
  for (auto _ : state) {
    hedra::hull::QuickhullResult r = builder.build(p.points);
    vertices = r.mesh.vertex_count();
    benchmark::DoNotOptimize(r);
  }
  set_counters(state, p, vertices);
}

void bench_qhull(benchmark::State& state, const PointSet* set, const char* options) {
  const Prepared& p = prepared(*set);
  long vertices = 0;
  for (auto _ : state) {
    vertices = hedra::reference::qhull_build_only(p.points.data(), p.points.size(), options);
    benchmark::DoNotOptimize(vertices);
  }
  if (vertices < 0) state.SkipWithError("qhull failed");
  set_counters(state, p, static_cast<std::size_t>(std::max(vertices, 0L)));
}

const bool registered = [] {
  for (const PointSet& set : point_sets()) {
    const PointSet* s = &set;
    for (auto* b : {benchmark::RegisterBenchmark((set.name + "/hedra").c_str(), bench_hedra, s),
                    benchmark::RegisterBenchmark((set.name + "/qhull").c_str(), bench_qhull, s, ""),
                    benchmark::RegisterBenchmark((set.name + "/qhull_Qt").c_str(), bench_qhull, s, "Qt")}) {
      b->Unit(benchmark::kMillisecond)->UseRealTime()->Repetitions(5)->ReportAggregatesOnly(true);
    }
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
