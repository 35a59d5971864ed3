// hedra's queries against libccd, FCL 0.7 and Bullet 3.24 on the same random
// pairs in one run, and the polyhedron support benchmark (hill-climbing vs
// linear scan) that picks support.hpp's crossover.
//
// Families (fixed seeds, generated once, outside the timed loops):
//   separated_poly    hull pairs of 8-64 vertices, separated      (distance)
//   penetrating_poly  hull pairs of 8-64 vertices, overlapping    (penetration)
//   hull1000          a 1 000-vertex hull vs a 16-vertex hull, half
//                     separated, half overlapping                  (penetration)
//   hull10000         the same with a 10 000-vertex hull           (penetration)
//   rounded           spheres, capsules and cylinders, mixed       (penetration)
// Each benchmark loops over its family's pairs, one query per iteration
// (time per iteration = time per query). Peers use their own objects, built
// once per pair outside the loop (peers.hpp: PreparedPair).
//
// Counters (computed once per method and family, outside timing):
//   error_median, error_max  |signed distance - exact reference| over the
//       pairs the method answered with a distance. The reference (polytope
//       families) is the signed distance from the origin to qhull's hull of
//       the Minkowski difference {a_i - b_j} (tools/reference), independent of
//       hedra's GJK/EPA. The rounded family has no reference here: no counter.
//   answered   pairs answered with a distance (libccd has no distance for
//       separated pairs: it only says "separated")
//   failures   pairs on which the method failed, crashed or timed out; those
//       were first run under run_isolated (fork + watchdog) and are left out
//       of the timed loop so that a peer's abort cannot end the run.
//
// Support benchmark: support/<mode>/<algorithm>/<vertices> over hulls of
// points on the unit sphere (every point a vertex), mode cold = independent
// random directions, warm = a direction rotating by 3 degrees per call
// about a slowly turning axis, the previous answer carried as the hint.
//
// Run with repetitions and read medians; tools/microbench/collision_table.py turns the
// --benchmark_format=json output into tables.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <hedra/collision/detail/support.hpp>
#include <hedra/collision/query.hpp>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "qhull_reference.hpp"
#ifdef HEDRA_WITH_PEERS
#  include "isolation.hpp"
#  include "peers.hpp"
#endif

namespace {

using namespace hedra::collision;
using Vec = Eigen::Vector3d;

double uniform(std::mt19937_64& engine, double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(engine() >> 11) * 0x1.0p-53);
}

Vec random_unit(std::mt19937_64& engine) {
  for (;;) {
    const Vec q(uniform(engine, -1, 1), uniform(engine, -1, 1), uniform(engine, -1, 1));
    const double n = q.norm();
    if (n <= 1.0 && n > 1e-3) return q / n;
  }
}

Eigen::Matrix3d random_rotation(std::mt19937_64& engine) {
  Eigen::Quaterniond q(uniform(engine, -1, 1), uniform(engine, -1, 1), uniform(engine, -1, 1), uniform(engine, -1, 1));
  return q.normalized().toRotationMatrix();
}

// n points on an ellipsoid with semi-axes `axes` (all vertices of the hull).
std::shared_ptr<const ConvexPolyhedron> random_hull(std::size_t n, const Vec& axes, std::mt19937_64& engine) {
  std::vector<Vec> points;
  for (std::size_t i = 0; i < n; ++i) points.push_back(random_unit(engine).cwiseProduct(axes));
  auto built = ConvexPolyhedron::build(points);
  if (!built.ok()) std::fprintf(stderr, "hull build failed: %s\n", built.message.c_str());
  return built.polyhedron;
}

struct Pair {
  Shape a;
  Pose pose_a;
  Shape b;
  Pose pose_b;
  double reference = std::numeric_limits<double>::quiet_NaN();  // exact signed distance
};

struct Family {
  std::string name;
  bool penetration = true;  // the query: penetration, else distance
  std::vector<Pair> pairs;
};

// ---- the exact reference ------------------------------------------------------

// Closest point to the origin on triangle abc (Voronoi regions of the
// vertices, edges and face; the textbook construction).
Vec closest_on_triangle(const Vec& a, const Vec& b, const Vec& c) {
  const Vec ab = b - a, ac = c - a, ap = -a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec bp = -b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec cp = -c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

std::vector<Vec> world_vertices(const Shape& s, const Pose& pose) {
  std::vector<Vec> out;
  const auto& hull = *std::get<Polyhedron>(s).hull;
  for (const Vec& v : hull.vertices()) out.push_back(pose.apply(v + hull.offset()));
  return out;
}

// Signed distance between two posed polytopes: + the distance from the
// origin to D = conv{a_i - b_j} when outside, - the smallest facet offset when
// inside. Coordinates are taken relative to A's centre (exact differences
// of nearby numbers).
double reference_signed_distance(const Pair& p) {
  const std::vector<Vec> a = world_vertices(p.a, p.pose_a), b = world_vertices(p.b, p.pose_b);
  std::vector<Vec> diff;
  diff.reserve(a.size() * b.size());
  for (const Vec& x : a)
    for (const Vec& y : b) diff.push_back(x - y);
  const hedra::reference::QhullHull h = hedra::reference::qhull_hull(diff, "Qt");
  if (!h.ok) return std::numeric_limits<double>::quiet_NaN();
  double outside = std::numeric_limits<double>::infinity(), inside = std::numeric_limits<double>::infinity();
  bool contains = true;
  for (const auto& t : h.triangles) {
    const Vec &p0 = diff[t[0]], &p1 = diff[t[1]], &p2 = diff[t[2]];
    const Vec n = (p1 - p0).cross(p2 - p0);
    if (!(n.norm() > 0.0)) continue;
    const Vec u = n.normalized();
    const double offset = (u.dot(p0) + u.dot(p1) + u.dot(p2)) / 3.0;  // origin is inside iff all > 0
    if (offset <= 0.0) contains = false;
    inside = std::min(inside, offset);
    outside = std::min(outside, closest_on_triangle(p0, p1, p2).norm());
  }
  return contains ? -inside : outside;
}

// ---- families ----------------------------------------------------------------

Pair polytope_pair(std::mt19937_64& e, std::size_t na, std::size_t nb, double ra, double rb, double centre_distance) {
  Pair p;
  p.a = Polyhedron{random_hull(na, ra * Vec(1.0, uniform(e, 0.5, 1.0), uniform(e, 0.5, 1.0)), e), 0.0};
  p.b = Polyhedron{random_hull(nb, rb * Vec(1.0, uniform(e, 0.5, 1.0), uniform(e, 0.5, 1.0)), e), 0.0};
  p.pose_a = Pose{random_rotation(e), Vec(uniform(e, -5, 5), uniform(e, -5, 5), uniform(e, -5, 5))};
  p.pose_b = Pose{random_rotation(e), p.pose_a.translation + centre_distance * random_unit(e)};
  p.reference = reference_signed_distance(p);
  return p;
}

Family separated_polytopes() {
  Family f{"separated_poly", false, {}};
  std::mt19937_64 e(11);
  while (f.pairs.size() < 64) {
    const std::size_t na = 8 + e() % 57, nb = 8 + e() % 57;
    Pair p = polytope_pair(e, na, nb, 1.0, uniform(e, 0.3, 1.0), 0.0);
    p.pose_b.translation = p.pose_a.translation + uniform(e, 1.5, 2.5) * random_unit(e);
    p.reference = reference_signed_distance(p);
    if (p.reference > 0.0) f.pairs.push_back(p);
  }
  return f;
}

Family penetrating_polytopes() {
  Family f{"penetrating_poly", true, {}};
  std::mt19937_64 e(12);
  while (f.pairs.size() < 64) {
    const std::size_t na = 8 + e() % 57, nb = 8 + e() % 57;
    Pair p = polytope_pair(e, na, nb, 1.0, uniform(e, 0.3, 1.0), uniform(e, 0.0, 1.0));
    if (p.reference < 0.0) f.pairs.push_back(p);
  }
  return f;
}

Family large_hulls(std::size_t n, std::uint64_t seed) {
  Family f{"hull" + std::to_string(n), true, {}};
  std::mt19937_64 e(seed);
  int separated = 0, overlapping = 0;
  while (separated + overlapping < 16) {
    Pair p = polytope_pair(e, n, 16, 1.0, 0.3, uniform(e, 0.6, 1.6));
    if (!std::isfinite(p.reference)) continue;
    int& count = p.reference > 0.0 ? separated : overlapping;
    if (count >= 8) continue;
    ++count;
    f.pairs.push_back(p);
  }
  return f;
}

Family rounded_shapes() {
  Family f{"rounded", true, {}};
  std::mt19937_64 e(13);
  const auto make = [&](int kind) -> Shape {
    if (kind == 0) return Sphere{uniform(e, 0.2, 1.0), 0.0};
    if (kind == 1) {
      const double half_length = uniform(e, 0.2, 1.0);  // drawn before the radius
      return Capsule{uniform(e, 0.1, 0.5), half_length, 0.0};
    }
    return Cylinder{uniform(e, 0.2, 1.0), uniform(e, 0.2, 1.0), 0.0};
  };
  for (int i = 0; i < 63; ++i) {
    const Shape a = make(i % 3), b = make((i / 3) % 3);
    const Pose pa{random_rotation(e), Vec(uniform(e, -5, 5), uniform(e, -5, 5), uniform(e, -5, 5))};
    const Pose pb{random_rotation(e), pa.translation + uniform(e, 0.2, 2.5) * random_unit(e)};
    const Pair p{a, pa, b, pb};
    f.pairs.push_back(p);
  }
  return f;
}

// ---- counters ----------------------------------------------------------------

struct Accuracy {
  std::vector<std::size_t> usable;  // pairs kept for timing
  double error_median = std::numeric_limits<double>::quiet_NaN();
  double error_max = std::numeric_limits<double>::quiet_NaN();
  int answered = 0;
  int failures = 0;
};

void finish_accuracy(Accuracy& acc, std::vector<double>& errors) {
  if (errors.empty()) return;
  std::sort(errors.begin(), errors.end());
  acc.error_median = errors[errors.size() / 2];
  acc.error_max = errors.back();
}

void set_counters(benchmark::State& state, const Accuracy& acc, std::size_t pairs) {
  state.counters["pairs"] = static_cast<double>(pairs);
  state.counters["answered"] = acc.answered;
  state.counters["failures"] = acc.failures;
  if (std::isfinite(acc.error_median)) {
    state.counters["error_median"] = acc.error_median;
    state.counters["error_max"] = acc.error_max;
  }
}

double hedra_signed_distance(const Family& f, const Pair& p) {
  if (f.penetration) return penetration(p.a, p.pose_a, p.b, p.pose_b).distance;
  return distance(p.a, p.pose_a, p.b, p.pose_b).distance;
}

void register_hedra(const Family& f) {
  Accuracy acc;
  std::vector<double> errors;
  for (std::size_t i = 0; i < f.pairs.size(); ++i) {
    acc.usable.push_back(i);
    const Pair& p = f.pairs[i];
    Status status = Status::ok;
    double d = 0.0;
    if (f.penetration) {
      const auto r = penetration(p.a, p.pose_a, p.b, p.pose_b);
      status = r.status;
      d = r.distance;
    } else {
      const auto r = distance(p.a, p.pose_a, p.b, p.pose_b);
      status = r.status;
      d = r.distance;
    }
    if (status != Status::ok) ++acc.failures;
    ++acc.answered;
    if (std::isfinite(p.reference)) errors.push_back(std::abs(d - p.reference));
  }
  finish_accuracy(acc, errors);
  benchmark::RegisterBenchmark(("collision/" + f.name + "/hedra").c_str(), [&f, acc](benchmark::State& state) {
    std::size_t i = 0;
    for (auto _ : state) {
      const Pair& p = f.pairs[i];
      benchmark::DoNotOptimize(hedra_signed_distance(f, p));
      if (++i == f.pairs.size()) i = 0;
    }
    set_counters(state, acc, f.pairs.size());
  });
}

#ifdef HEDRA_WITH_PEERS
void register_peer(const Family& f, const hedra::peers::PeerMethod& m) {
  using hedra::peers::PeerQuery;
  const PeerQuery query = f.penetration ? PeerQuery::penetration : PeerQuery::distance;
  hedra::peers::IsolationSettings isolation;
  isolation.timeout_seconds = 10.0;
  const auto results = hedra::peers::run_isolated(
      [&](std::size_t i) {
        const Pair& p = f.pairs[i];
        return m.run({p.a, p.pose_a, p.b, p.pose_b}, query);
      },
      f.pairs.size(), isolation);
  auto acc = std::make_shared<Accuracy>();
  std::vector<double> errors;
  bool supported = false;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const auto& r = results[i];
    if (!r.supported) continue;
    supported = true;
    if (!r.ok) {
      ++acc->failures;
      if (r.status.rfind("crashed", 0) == 0 || r.status.rfind("timeout", 0) == 0) continue;  // never in-process
    }
    acc->usable.push_back(i);
    if (r.ok && r.has_distance) {
      ++acc->answered;
      if (std::isfinite(f.pairs[i].reference)) errors.push_back(std::abs(r.distance - f.pairs[i].reference));
    }
  }
  if (!supported || acc->usable.empty()) return;
  finish_accuracy(*acc, errors);
  // The peer's objects for the usable pairs, built once.
  auto prepared = std::make_shared<std::vector<std::unique_ptr<hedra::peers::PreparedPair>>>();
  for (std::size_t i : acc->usable) {
    const Pair& p = f.pairs[i];
    prepared->push_back(m.prepare({p.a, p.pose_a, p.b, p.pose_b}));
  }
  benchmark::RegisterBenchmark(("collision/" + f.name + "/" + m.name).c_str(),
                               [&f, acc, prepared, query](benchmark::State& state) {
                                 std::size_t i = 0;
                                 for (auto _ : state) {
                                   benchmark::DoNotOptimize((*prepared)[i]->query(query).distance);
                                   if (++i == prepared->size()) i = 0;
                                 }
                                 set_counters(state, *acc, f.pairs.size());
                               });
}
#endif

// ---- support ------------------------------------------------------------------

struct SupportCase {
  std::shared_ptr<const ConvexPolyhedron> hull;
  std::vector<Vec> cold, warm;
};

std::vector<Vec> rotating_directions(std::size_t count, std::mt19937_64& e) {
  std::vector<Vec> out;
  Vec d = random_unit(e);
  Vec axis = random_unit(e);
  const double step = 3.0 * M_PI / 180.0;
  for (std::size_t i = 0; i < count; ++i) {
    axis = (axis + 0.05 * random_unit(e)).normalized();
    d = Eigen::AngleAxisd(step, axis) * d;
    out.push_back(d);
  }
  return out;
}

void register_support(std::size_t n) {
  auto c = std::make_shared<SupportCase>();
  std::mt19937_64 e(1000 + n);
  std::vector<Vec> points;
  for (std::size_t i = 0; i < n; ++i) points.push_back(random_unit(e));
  c->hull = ConvexPolyhedron::build(points).polyhedron;
  for (int i = 0; i < 4096; ++i) c->cold.push_back(random_unit(e));
  c->warm = rotating_directions(4096, e);
  const std::string v = std::to_string(c->hull->vertex_count());
  for (const char* mode : {"cold", "warm"}) {
    const bool warm = std::string(mode) == "warm";
    benchmark::RegisterBenchmark(("support/" + std::string(mode) + "/scan/" + v).c_str(),
                                 [c, warm](benchmark::State& state) {
                                   const auto& dirs = warm ? c->warm : c->cold;
                                   std::size_t i = 0;
                                   for (auto _ : state) {
                                     benchmark::DoNotOptimize(polyhedron_support_scan(*c->hull, dirs[i]));
                                     i = (i + 1) & 4095;
                                   }
                                 });
    benchmark::RegisterBenchmark(("support/" + std::string(mode) + "/climb/" + v).c_str(),
                                 [c, warm](benchmark::State& state) {
                                   const auto& dirs = warm ? c->warm : c->cold;
                                   std::size_t i = 0;
                                   hedra::hull::Index hint = 0;
                                   for (auto _ : state) {
                                     hint = polyhedron_support_climb(*c->hull, dirs[i], hint);
                                     benchmark::DoNotOptimize(hint);
                                     i = (i + 1) & 4095;
                                   }
                                 });
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  // Families live until the end of main: the benchmarks refer to them.
  static const std::vector<Family> families = {separated_polytopes(), penetrating_polytopes(), large_hulls(1000, 14),
                                               large_hulls(10000, 15), rounded_shapes()};
  for (const Family& f : families) {
    register_hedra(f);
#ifdef HEDRA_WITH_PEERS
    for (const auto& m : hedra::peers::peer_methods()) register_peer(f, m);
#endif
  }
  for (std::size_t n : {8, 16, 32, 64, 128, 256, 1000, 10000, 100000}) register_support(n);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
