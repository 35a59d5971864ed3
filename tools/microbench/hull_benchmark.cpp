// hedra's quickhull against qhull (libqhull_r, through tools/reference) on the
// same point sets, side by side in one run:
//   ball/N      uniform in the unit ball, N = 1e3, 1e5, 1e6
//   sphere/N    on the unit sphere (every point is a vertex), N = 1e4, 1e5
//   cube_grid/N a 100 x 100 integer grid on each face of a cube, shared edge
//               and corner points once (heavy coplanarity: 8 vertices)
//   slab/N      a 2 x 2 square 1e-9 thick, turned off the axes (nearly flat:
//               merging decides almost every face)
//   cylinder/N  on the curved surface of a cylinder (radius 1, height 2):
//               long thin, nearly coplanar faces along its length
//   duplicates/N N/2 points on the unit sphere, each twice (the copy exact,
//               or moved by 1e-15)
//   far/N       uniform in the unit ball centred at (1e6, -1e6, 1e6)
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
//   bytes_per_point   peak heap bytes of one hedra build with a new builder
//                     (working memory and result), per input point; counted
//                     by this program's operator new
// hedra's builder is reused across iterations (and warmed up once), as an
// application building many hulls would. Run with repetitions and read
// medians: tools/microbench/hull_table.py turns --benchmark_format=json output into a
// table. `hull_benchmark --memory` prints only the memory per point, for these
// sets and a sphere of 1e6 points (too slow to time here); `--digest` a hash
// of each build's whole output (these sets and 520 small clouds), to compare
// two builds bit for bit; `--once SET` one build of SET, for callgrind.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <hedra/hull/quickhull.hpp>
#include <map>
#include <new>
#include <random>
#include <string>
#include <vector>

#include "qhull_reference.hpp"

// Heap accounting: every operator new of this program goes through these
// (8-byte size header), so the peak of one build can be read off.
namespace heap {
std::size_t current = 0, peak = 0;
}  // namespace heap

void* operator new(std::size_t size) {
  void* block = std::malloc(size + 16);
  if (block == nullptr) throw std::bad_alloc();
  std::memcpy(block, &size, sizeof size);
  heap::current += size;
  heap::peak = std::max(heap::peak, heap::current);
  return static_cast<char*>(block) + 16;
}
void operator delete(void* p) noexcept {
  if (p == nullptr) return;
  char* block = static_cast<char*>(p) - 16;
  std::size_t size = 0;
  std::memcpy(&size, block, sizeof size);
  heap::current -= size;
  std::free(block);
}
void* operator new[](std::size_t size) { return operator new(size); }
void operator delete[](void* p) noexcept { operator delete(p); }
void operator delete(void* p, std::size_t) noexcept { operator delete(p); }
void operator delete[](void* p, std::size_t) noexcept { operator delete(p); }

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

// Fisher-Yates with the engine's raw bits (standard-fixed, like uniform()).
void shuffle(Points& p, std::mt19937_64& engine) {
  for (std::size_t i = p.size(); i > 1; --i) std::swap(p[i - 1], p[engine() % i]);
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
  shuffle(p, engine);
  return p;
}

// The curved surface of the cylinder x^2 + y^2 = 1, |z| <= 1.
Points cylinder_surface(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  Points p;
  p.reserve(n);
  while (p.size() < n) {
    const double a = uniform(engine, 0, 6.283185307179586), z = uniform(engine, -1, 1);
    p.emplace_back(std::cos(a), std::sin(a), z);
  }
  return p;
}

// A 2 x 2 x 1e-9 slab, turned by a fixed rotation so no face is axis-aligned.
Points thin_slab(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitZ()))
          .toRotationMatrix();
  Points p;
  p.reserve(n);
  while (p.size() < n)
    p.push_back(turn * Eigen::Vector3d(uniform(engine, -1, 1), uniform(engine, -1, 1), uniform(engine, -5e-10, 5e-10)));
  return p;
}

// n/2 points on the unit sphere, each twice: the copy exact or moved by
// 1e-15 (below the tolerance), in shuffled order.
Points duplicated_sphere(std::size_t n, std::uint64_t seed) {
  Points p = sphere_surface(n / 2, seed);
  std::mt19937_64 engine(seed + 1);
  for (std::size_t i = 0, half = p.size(); i < half; ++i)
    p.push_back(engine() % 2 ? p[i] : Eigen::Vector3d(p[i] + Eigen::Vector3d(1e-15, -1e-15, 0.5e-15)));
  shuffle(p, engine);
  return p;
}

// The unit ball, moved 1e6 away along each axis.
Points far_ball(std::size_t n, std::uint64_t seed) {
  Points p = uniform_ball(n, seed);
  for (auto& q : p) q += Eigen::Vector3d(1e6, -1e6, 1e6);
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
      {"slab/10000", [] { return thin_slab(10000, 7); }},
      {"slab/100000", [] { return thin_slab(100000, 8); }},
      {"cylinder/10000", [] { return cylinder_surface(10000, 9); }},
      {"cylinder/100000", [] { return cylinder_surface(100000, 10); }},
      {"duplicates/100000", [] { return duplicated_sphere(100000, 11); }},
      {"far/100000", [] { return far_ball(100000, 12); }},
  };
  return sets;
}

// Per set, computed once: the points and the vertex-set comparison.
struct Prepared {
  Points points;
  std::size_t hedra_vertices = 0;
  std::size_t qhull_vertices = 0;
  bool vertex_sets_equal = false;
  double bytes_per_point = 0;
};

// Peak heap bytes per input point of one build with a new builder.
double build_bytes_per_point(const Points& points) {
  const std::size_t before = heap::current;
  heap::peak = before;
  {
    hedra::hull::QuickhullBuilder builder;
    const hedra::hull::QuickhullResult r = builder.build(points);
    benchmark::DoNotOptimize(r.mesh.vertex_count());
  }
  return static_cast<double>(heap::peak - before) / static_cast<double>(points.size());
}

const Prepared& prepared(const PointSet& set) {
  static std::map<std::string, Prepared> cache;
  auto it = cache.find(set.name);
  if (it != cache.end()) return it->second;
  Prepared p;
  p.points = set.make();
  p.bytes_per_point = build_bytes_per_point(p.points);
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
  state.counters["bytes_per_point"] = p.bytes_per_point;
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

// --memory: the peak heap bytes per point of one build, per set.
int print_memory() {
  std::vector<PointSet> sets = point_sets();
  sets.push_back({"sphere/1000000", [] { return sphere_surface(1000000, 13); }});
  for (const PointSet& set : sets) {
    const Points points = set.make();
    std::printf("%-20s %9zu points  %7.0f bytes per point\n", set.name.c_str(), points.size(),
                build_bytes_per_point(points));
  }
  return 0;
}

// --digest: one line per cloud (these sets and 520 small random and
// degenerate ones) with a 64-bit FNV-1a hash of everything a build returns:
// status, tolerance, dimension, iterations, input indices, vertices, and
// every half-edge's links and face's plane, bit for bit. Two builds of the
// library whose digests match gave the same answers on every cloud.
struct Digest {
  std::uint64_t h = 1469598103934665603ull;
  void bytes(const void* data, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
  template <class T>
  void add(const T& v) {
    bytes(&v, sizeof v);
  }
};

std::uint64_t result_digest(const hedra::hull::QuickhullResult& r) {
  Digest d;
  d.add(static_cast<int>(r.status));
  d.add(r.tolerance), d.add(r.dimension), d.add(r.iterations), d.add(r.mesh.tolerance());
  for (hedra::hull::Index i : r.input_index) d.add(i);
  for (const auto& v : r.mesh.vertices)
    d.add(v.position.x()), d.add(v.position.y()), d.add(v.position.z()), d.add(v.edge);
  for (const auto& e : r.mesh.edges) d.add(e.origin), d.add(e.twin), d.add(e.next), d.add(e.prev), d.add(e.face);
  for (const auto& f : r.mesh.faces) {
    d.add(f.edge);
    d.add(f.plane.normal.x()), d.add(f.plane.normal.y()), d.add(f.plane.normal.z()), d.add(f.plane.offset);
  }
  d.bytes(r.error.data(), r.error.size());
  return d.h;
}

// Small clouds of every kind that makes quickhull decide near its
// tolerance: 40 seeds of each of 13 families.
Points digest_cloud(int family, std::uint64_t seed) {
  std::mt19937_64 engine(seed * 131 + static_cast<std::uint64_t>(family));
  const std::size_t n = 4 + engine() % 1500;
  const Eigen::Matrix3d turn = (Eigen::AngleAxisd(uniform(engine, 0, 3), Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(uniform(engine, 0, 3), Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix();
  Points p;
  switch (family) {
    case 0:
      return uniform_ball(n, seed);
    case 1:
      return sphere_surface(n, seed);
    case 2:
      return cylinder_surface(n, seed);
    case 3:
    case 4:  // slabs 1e-10 and 1e-14 thick, turned
      for (std::size_t i = 0; i < n; ++i) {
        const double t = family == 3 ? 1e-10 : 1e-14;
        p.push_back(turn * Eigen::Vector3d(uniform(engine, -1, 1), uniform(engine, -1, 1), uniform(engine, -t, t)));
      }
      return p;
    case 5:  // exact duplicates and 1e-15 moves
      p = sphere_surface(n / 2 + 2, seed);
      for (std::size_t i = 0, half = p.size(); i < half; ++i)
        p.push_back(engine() % 2 ? p[i] : Eigen::Vector3d(p[i] + Eigen::Vector3d(1e-15, -1e-15, 0.5e-15)));
      shuffle(p, engine);
      return p;
    case 6:  // clusters of near-duplicates
      for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d q = sphere_surface(1, seed * 7 + engine() % 12)[0];
        p.push_back(q +
                    1e-12 * Eigen::Vector3d(uniform(engine, -1, 1), uniform(engine, -1, 1), uniform(engine, -1, 1)));
      }
      return p;
    case 7:  // stretched, far from the origin
      for (const auto& q : uniform_ball(n, seed))
        p.push_back(turn * Eigen::Vector3d(1e3 * q.x(), q.y(), 1e-3 * q.z()) + Eigen::Vector3d(1e5, 0, -3e4));
      return p;
    case 8:  // sphere points rounded to a 1/64 grid
      for (const auto& q : sphere_surface(n, seed)) p.push_back((q * 64).array().round().matrix() / 64);
      return p;
    case 9:  // coplanar, turned
      for (std::size_t i = 0; i < n; ++i)
        p.push_back(turn * Eigen::Vector3d(uniform(engine, -1, 1), uniform(engine, -1, 1), 0));
      return p;
    case 10:  // collinear, turned
      for (std::size_t i = 0; i < n; ++i) p.push_back(turn * Eigen::Vector3d(uniform(engine, -1, 1), 0, 0));
      return p;
    case 11: {  // integer lattice in a box
      const int k = 2 + static_cast<int>(engine() % 7);
      for (int x = 0; x < k; ++x)
        for (int y = 0; y < k; ++y)
          for (int z = 0; z < k; ++z) p.emplace_back(x, y, z);
      shuffle(p, engine);
      return p;
    }
    default:
      return cube_grid(3 + static_cast<int>(engine() % 20), seed);
  }
}

int print_digests() {
  hedra::hull::QuickhullBuilder builder;  // reused, as the benchmark does
  for (const PointSet& set : point_sets())
    std::printf("%-20s %016llx\n", set.name.c_str(),
                static_cast<unsigned long long>(result_digest(builder.build(set.make()))));
  for (int family = 0; family < 13; ++family)
    for (std::uint64_t seed = 0; seed < 40; ++seed)
      std::printf("cloud/%d/%llu %016llx\n", family, static_cast<unsigned long long>(seed),
                  static_cast<unsigned long long>(result_digest(builder.build(digest_cloud(family, seed)))));
  return 0;
}

// --once SET: one build of SET with a new builder (for callgrind:
// --toggle-collect='hedra::hull::QuickhullBuilder::build*').
int build_once(const char* name) {
  for (const PointSet& set : point_sets()) {
    if (set.name != name) continue;
    const Points points = set.make();
    hedra::hull::QuickhullBuilder builder;
    const hedra::hull::QuickhullResult r = builder.build(points);
    std::printf("%s: %zu vertices\n", name, r.mesh.vertex_count());
    return 0;
  }
  std::fprintf(stderr, "no set %s\n", name);
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--memory") == 0) return print_memory();
    if (std::strcmp(argv[i], "--digest") == 0) return print_digests();
    if (std::strcmp(argv[i], "--once") == 0 && i + 1 < argc) return build_once(argv[i + 1]);
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
