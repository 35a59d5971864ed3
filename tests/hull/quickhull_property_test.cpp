// Property tests of quickhull over thousands of small random clouds (4 to 200
// points) from several distributions, each cloud replayable from its seed
// (HEDRA_REPLAY_SEED=<seed> runs only that cloud and prints it). For every
// cloud:
//   * the build succeeds and is sound (soundness_problem: vertices are input
//     points, validate() passes, every point is inside or within
//     kOutsideFactor * tolerance, by hedra's max_outside_distance and by an
//     independent measure);
//   * on general-position distributions where qhull ("Qt Qc") reports no
//     coplanar point and no merged facet, the vertex set equals qhull's
//     exactly and the volume agrees within 1e-12 relative;
//   * the result does not depend on input order or on duplicated points:
//     the same vertex positions and volume (within 1e-12 relative) where the
//     input is in general position; elsewhere each hull contains the other's
//     vertices within the tolerance and the volumes differ by at most the
//     tolerance times the area.
// Failures list every failing seed and print the first few clouds at %.17g.
#include <gtest/gtest.h>

#include <map>

#include "qhull_reference.hpp"
#include "quickhull_test_support.hpp"

namespace hedra::test {
namespace {

using hull::QuickhullBuilder;
using hull::QuickhullResult;
using Points = std::vector<Eigen::Vector3d>;

enum class Distribution {
  uniform_ball,
  uniform_cube,
  sphere_surface,
  gaussian,
  clustered,        // 1-4 centres, jitter 1e-14 ... 1e-2 of the spread
  near_plane,       // a tilted disk, thickness 1e-17 ... 1e-6 of its size
  near_line,        // a tilted segment, radial noise 1e-17 ... 1e-6 of its length
  integer_lattice,  // coordinates in {-2..2}: duplicates, exact coplanarity and collinearity
};

const char* name(Distribution d) {
  switch (d) {
    case Distribution::uniform_ball:
      return "uniform_ball";
    case Distribution::uniform_cube:
      return "uniform_cube";
    case Distribution::sphere_surface:
      return "sphere_surface";
    case Distribution::gaussian:
      return "gaussian";
    case Distribution::clustered:
      return "clustered";
    case Distribution::near_plane:
      return "near_plane";
    case Distribution::near_line:
      return "near_line";
    case Distribution::integer_lattice:
      return "integer_lattice";
  }
  return "?";
}

// Distributions whose clouds are in general position with probability 1; the
// strict comparisons apply to them once qhull confirms it cloud by cloud.
bool general(Distribution d) {
  return d == Distribution::uniform_ball || d == Distribution::uniform_cube || d == Distribution::sphere_surface ||
         d == Distribution::gaussian;
}

Points generate(Distribution d, std::uint64_t seed) {
  Rng rng(seed);
  const std::size_t n = 4 + rng.below(197);
  Points p;
  p.reserve(n);
  switch (d) {
    case Distribution::uniform_ball:
      for (std::size_t i = 0; i < n; ++i) p.push_back(rng.in_ball());
      break;
    case Distribution::uniform_cube:
      for (std::size_t i = 0; i < n; ++i) p.push_back(rng.in_cube());
      break;
    case Distribution::sphere_surface:
      for (std::size_t i = 0; i < n; ++i) p.push_back(rng.on_sphere());
      break;
    case Distribution::gaussian:
      for (std::size_t i = 0; i < n; ++i) p.push_back(rng.gaussian());
      break;
    case Distribution::clustered: {
      Points centres(1 + rng.below(4));
      for (auto& c : centres) c = rng.in_ball();
      const double jitter = std::pow(10.0, rng.uniform(-14, -2));
      for (std::size_t i = 0; i < n; ++i) p.push_back(centres[rng.below(centres.size())] + jitter * rng.in_ball());
      break;
    }
    case Distribution::near_plane: {
      const Eigen::Matrix3d rot = rng.rotation();
      const double thickness = std::pow(10.0, rng.uniform(-17, -6));
      for (std::size_t i = 0; i < n; ++i) {
        Eigen::Vector2d q;
        do q = Eigen::Vector2d(rng.uniform(-1, 1), rng.uniform(-1, 1));
        while (q.squaredNorm() > 1.0);
        p.push_back(q.x() * rot.col(0) + q.y() * rot.col(1) + thickness * rng.uniform(-1, 1) * rot.col(2));
      }
      break;
    }
    case Distribution::near_line: {
      const Eigen::Matrix3d rot = rng.rotation();
      const double noise = std::pow(10.0, rng.uniform(-17, -6));
      for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector2d q = noise * Eigen::Vector2d(rng.uniform(-1, 1), rng.uniform(-1, 1));
        p.push_back(rng.uniform(-1, 1) * rot.col(0) + q.x() * rot.col(1) + q.y() * rot.col(2));
      }
      break;
    }
    case Distribution::integer_lattice:
      for (std::size_t i = 0; i < n; ++i) {
        p.emplace_back(static_cast<double>(rng.below(5)) - 2, static_cast<double>(rng.below(5)) - 2,
                       static_cast<double>(rng.below(5)) - 2);
      }
      break;
  }
  return p;
}

double relative_difference(double a, double b) { return std::abs(a - b) / std::max(std::abs(a), std::abs(b)); }

// Empty when hulls a and b (of inputs with the same points) agree: exactly in
// general position, else within the tolerance both ways.
std::string describe(const QuickhullResult& r) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "dimension %d, %zu vertices, %zu faces, tolerance %.3g, volume %.17g, area %.17g",
                r.dimension, r.mesh.vertex_count(), r.mesh.face_count(), r.tolerance, mesh_volume(r.mesh),
                mesh_area(r.mesh));
  return buf;
}

std::string compare_hulls(const QuickhullResult& a, const QuickhullResult& b, bool strict) {
  const std::string both = "\n    first:  " + describe(a) + "\n    second: " + describe(b);
  char buf[256];
  if (strict) {
    if (sorted_positions(a.mesh) != sorted_positions(b.mesh)) {
      return "vertex positions differ" + both;
    }
    const double va = mesh_volume(a.mesh);
    const double vb = mesh_volume(b.mesh);
    if (relative_difference(va, vb) > 1e-12) {
      std::snprintf(buf, sizeof buf, "volumes %.17g vs %.17g", va, vb);
      return buf + both;
    }
    return {};
  }
  const double tol = std::max(a.tolerance, b.tolerance);
  for (const auto* pair : {&a, &b}) {
    const QuickhullResult& outer = *pair;
    const QuickhullResult& inner = pair == &a ? b : a;
    const OutsideMeasure measure(outer.mesh);
    for (const auto& v : inner.mesh.vertices) {
      const double d = measure(v.position);
      if (d > kOutsideFactor * tol) {
        std::snprintf(buf, sizeof buf, "a vertex of the %s hull is %.3g tolerances outside the other",
                      pair == &a ? "second" : "first", d / tol);
        return buf + both;
      }
    }
  }
  const double dv = std::abs(mesh_volume(a.mesh) - mesh_volume(b.mesh));
  const double allowed = kOutsideFactor * tol * std::max(mesh_area(a.mesh), mesh_area(b.mesh));
  if (dv > allowed) {
    std::snprintf(buf, sizeof buf, "volumes differ by %.17g > %.17g", dv, allowed);
    return buf + both;
  }
  return {};
}

struct SuiteStats {
  std::size_t clouds = 0;
  std::size_t qhull_compared = 0;
  std::map<int, std::size_t> dimensions;
  std::vector<std::string> failures;  // one line each: seed and what failed
  std::string first_dumps;            // the first few failing clouds in full
};

void fail(SuiteStats& stats, Distribution d, std::uint64_t seed, const Points& points, const std::string& what) {
  char head[160];
  std::snprintf(head, sizeof head, "%s seed %llu (%zu points): ", name(d), static_cast<unsigned long long>(seed),
                points.size());
  stats.failures.push_back(head + what);
  if (stats.failures.size() <= 3) stats.first_dumps += std::string(head) + what + "\ninput " + format_points(points);
}

void check_cloud(Distribution d, std::uint64_t seed, QuickhullBuilder& builder, SuiteStats& stats, bool verbose) {
  const Points points = generate(d, seed);
  if (verbose)
    std::printf("%s seed %llu\ninput %s", name(d), static_cast<unsigned long long>(seed),
                format_points(points).c_str());
  const std::string label = std::string(name(d)) + " seed " + std::to_string(seed);
  ++stats.clouds;
  const QuickhullResult r = guarded_build(builder, points, label);
  const std::string problem = soundness_problem(r, points);
  if (!problem.empty()) return fail(stats, d, seed, points, problem);
  ++stats.dimensions[r.dimension];

  // The reused builder gives what a fresh one gives (every 16th cloud).
  if (seed % 16 == 0) {
    QuickhullBuilder fresh_builder;
    const QuickhullResult fresh = guarded_build(fresh_builder, points, label + " (fresh builder)");
    if (fresh.input_index != r.input_index || fresh.mesh.polygons() != r.mesh.polygons())
      return fail(stats, d, seed, points, "a reused builder and a fresh one give different hulls");
  }

  // The independent reference.
  bool strict = false;
  if (general(d)) {
    const reference::QhullHull q = reference::qhull_hull(points, "Qt Qc");
    if (q.leaked_bytes != 0) return fail(stats, d, seed, points, "qhull leaked memory (reference broken)");
    if (q.general_position()) {
      strict = true;
      ++stats.qhull_compared;
      std::vector<int> mine;
      for (hull::Index i : sorted_input_indices(r)) mine.push_back(static_cast<int>(i));
      if (r.dimension != 3 || mine != q.vertices) {
        return fail(stats, d, seed, points,
                    "vertex set differs from qhull's (" + std::to_string(mine.size()) + " vs " +
                        std::to_string(q.vertices.size()) + " vertices)");
      }
      const double volume = mesh_volume(r.mesh);
      if (relative_difference(volume, q.volume) > 1e-12) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "volume %.17g, qhull %.17g", volume, q.volume);
        return fail(stats, d, seed, points, buf);
      }
    }
  }

  // Order and duplicates.
  Rng rng(seed ^ 0x9e3779b97f4a7c15ULL);
  Points shuffled = points;
  shuffle_points(shuffled, rng);
  const QuickhullResult rs = guarded_build(builder, shuffled, label + " (shuffled)");
  std::string why = soundness_problem(rs, shuffled);
  if (why.empty()) why = compare_hulls(r, rs, strict);
  if (!why.empty()) return fail(stats, d, seed, points, "shuffled input: " + why);

  Points repeated = points;
  const std::size_t extra = 1 + rng.below(2 * points.size());
  for (std::size_t k = 0; k < extra; ++k) repeated.push_back(points[rng.below(points.size())]);
  shuffle_points(repeated, rng);
  const QuickhullResult rd = guarded_build(builder, repeated, label + " (with duplicates)");
  why = soundness_problem(rd, repeated);
  if (why.empty()) why = compare_hulls(r, rd, strict);
  if (!why.empty()) return fail(stats, d, seed, points, "input with duplicates: " + why);
}

SuiteStats run_suite(Distribution d, std::size_t count) {
  SuiteStats stats;
  QuickhullBuilder builder;  // reused across the whole suite
  const std::uint64_t base = 1000000ULL * (static_cast<std::uint64_t>(d) + 1);
  const long long replay = replay_seed();
  for (std::uint64_t seed = base; seed < base + count; ++seed) {
    if (replay >= 0 && static_cast<std::uint64_t>(replay) != seed) continue;
    check_cloud(d, seed, builder, stats, replay >= 0);
  }
  return stats;
}

void report(const SuiteStats& stats) {
  std::printf("%zu clouds, %zu compared with qhull, dimensions:", stats.clouds, stats.qhull_compared);
  for (const auto& [dimension, count] : stats.dimensions) std::printf(" %d: %zu", dimension, count);
  std::printf("\n");
  std::string summary;
  for (const auto& line : stats.failures) summary += "  " + line + "\n";
  EXPECT_TRUE(stats.failures.empty()) << stats.failures.size() << " of " << stats.clouds << " clouds failed:\n"
                                      << summary << "first failing clouds:\n"
                                      << stats.first_dumps;
}

// The strict comparisons must not be skipped wholesale: qhull has to confirm
// general position for at least 90% of a general distribution's clouds.
void expect_mostly_compared(const SuiteStats& stats) {
  EXPECT_GE(stats.qhull_compared, stats.clouds * 9 / 10) << "qhull saw too few clean clouds";
}

constexpr std::size_t kCloudsPerSuite = 500;

TEST(QuickhullProperty, UniformBallMatchesQhullAndIgnoresOrderAndDuplicates) {
  const SuiteStats stats = run_suite(Distribution::uniform_ball, kCloudsPerSuite);
  report(stats);
  expect_mostly_compared(stats);
}

TEST(QuickhullProperty, UniformCubeMatchesQhullAndIgnoresOrderAndDuplicates) {
  const SuiteStats stats = run_suite(Distribution::uniform_cube, kCloudsPerSuite);
  report(stats);
  expect_mostly_compared(stats);
}

TEST(QuickhullProperty, SphereSurfaceMatchesQhullAndKeepsEveryPoint) {
  const SuiteStats stats = run_suite(Distribution::sphere_surface, kCloudsPerSuite);
  report(stats);
  expect_mostly_compared(stats);
}

TEST(QuickhullProperty, GaussianMatchesQhullAndIgnoresOrderAndDuplicates) {
  const SuiteStats stats = run_suite(Distribution::gaussian, kCloudsPerSuite);
  report(stats);
  expect_mostly_compared(stats);
}

TEST(QuickhullProperty, ClusteredCloudsAreSoundAndStable) {
  report(run_suite(Distribution::clustered, kCloudsPerSuite));
}

TEST(QuickhullProperty, NearPlanarCloudsAreSoundAndStable) {
  const SuiteStats stats = run_suite(Distribution::near_plane, kCloudsPerSuite);
  report(stats);
  // Thickness spans the tolerance: both flat and solid hulls must occur.
  if (replay_seed() < 0) {
    EXPECT_GT(stats.dimensions.count(2) ? stats.dimensions.at(2) : 0, 0u);
    EXPECT_GT(stats.dimensions.count(3) ? stats.dimensions.at(3) : 0, 0u);
  }
}

TEST(QuickhullProperty, NearLinearCloudsAreSoundAndStable) {
  const SuiteStats stats = run_suite(Distribution::near_line, kCloudsPerSuite);
  report(stats);
  // Noise spans the tolerance: segments and non-segments must both occur.
  if (replay_seed() < 0) {
    EXPECT_GT(stats.dimensions.count(1) ? stats.dimensions.at(1) : 0, 0u);
    EXPECT_GT(stats.clouds - (stats.dimensions.count(1) ? stats.dimensions.at(1) : 0), 0u);
  }
}

TEST(QuickhullProperty, IntegerLatticeCloudsAreSoundAndStable) {
  report(run_suite(Distribution::integer_lattice, kCloudsPerSuite));
}

}  // namespace
}  // namespace hedra::test
