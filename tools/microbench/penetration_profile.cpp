// A repeatable driver for profiling penetration() on `hedra bench`'s pairs.
//
//   penetration_cases dump FILE FAMILY...   generate the bench's pairs of
//       those families (seed 1, tools/cli/bench/workloads.cpp) with their exact
//       references and write them to FILE (text, %.17g: replayed bit for bit)
//   penetration_profile run FILE [--family NAME] [--repeat N] [--time] [--answers OUT] [--query Q]
//       replay them: N penetration() calls per pair (cold, as the bench
//       runs hedra), then per family the queries, the largest error against
//       the reference (absolute and relative to the pair's size), failures
//       by the bench's rules (error above reference bound + 1e-6 size, a
//       normal more than 1e-3 rad off a unique reference normal, a cap, a
//       NaN), mean GJK/EPA iterations and support calls, and a hash of every
//       answer (distance, normal, witnesses: equal hashes, answers equal bit
//       for bit); --time adds the median over 7 loops of ns per query;
//       --answers OUT writes every answer (family, index, status, distance,
//       error bound, normal, witnesses, the exact distance, its bound and the
//       pair's size; %.17g) to compare two builds answer by answer.
//       --query distance: distance() instead, on the pairs `hedra bench
//       --query distance` asks (exact distance above its bound + 1e-6 size),
//       failures by the same rules (an overlap verdict, an error, a normal);
//       --query intersect: intersect() on every pair, a failure being a
//       verdict other than the exact sign where |exact| exceeds that
//       tolerance, or a status other than ok; the hash covers what each
//       query answers (distance, normal, witnesses; the verdict).
// Two executables from this file: penetration_cases (with the bench's
// workloads, for `dump`) and penetration_profile (`run` only, so that a
// change to the collision headers rebuilds little).
//
// Instruction counts: everything but the queries (reading the file, building
// the hulls) stays outside `hedra::collision::penetration`, so
//   valgrind --tool=callgrind --toggle-collect='hedra::collision::penetration(*'
//            build/bin/penetration_profile run FILE --family poly-penetrating
// counts the queries alone; divide the total by the queries printed (with
// --query, toggle on 'hedra::collision::distance(*' or '...intersect(*').
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <hedra/collision/query.hpp>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#if defined(HEDRA_PROFILE_DUMP)
#  include "cli/bench/workloads.hpp"
#endif

namespace {

using hedra::collision::Pose;
using hedra::collision::Shape;
namespace col = hedra::collision;

#if defined(HEDRA_PROFILE_DUMP)
std::string num(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

void write_shape(std::ostream& out, const Shape& s, const std::vector<Eigen::Vector3d>& points) {
  if (const auto* p = std::get_if<col::Sphere>(&s)) out << "sphere " << num(p->radius) << ' ' << num(p->margin);
  if (const auto* p = std::get_if<col::Box>(&s))
    out << "box " << num(p->half_extents.x()) << ' ' << num(p->half_extents.y()) << ' ' << num(p->half_extents.z())
        << ' ' << num(p->margin);
  if (const auto* p = std::get_if<col::Capsule>(&s))
    out << "capsule " << num(p->radius) << ' ' << num(p->half_length) << ' ' << num(p->margin);
  if (const auto* p = std::get_if<col::Cylinder>(&s))
    out << "cylinder " << num(p->radius) << ' ' << num(p->half_length) << ' ' << num(p->margin);
  if (const auto* p = std::get_if<col::Cone>(&s))
    out << "cone " << num(p->radius) << ' ' << num(p->half_length) << ' ' << num(p->margin);
  if (const auto* p = std::get_if<col::Polyhedron>(&s)) {
    out << "poly " << num(p->margin) << ' ' << points.size();
    for (const Eigen::Vector3d& x : points) out << ' ' << num(x.x()) << ' ' << num(x.y()) << ' ' << num(x.z());
  }
  out << '\n';
}

void write_pose(std::ostream& out, const Pose& p) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out << num(p.rotation(i, j)) << ' ';
  out << num(p.translation.x()) << ' ' << num(p.translation.y()) << ' ' << num(p.translation.z()) << '\n';
}

#endif

Shape read_shape(std::istream& in) {
  std::string kind;
  in >> kind;
  if (kind == "sphere") {
    col::Sphere s;
    in >> s.radius >> s.margin;
    return s;
  }
  if (kind == "box") {
    col::Box s;
    in >> s.half_extents.x() >> s.half_extents.y() >> s.half_extents.z() >> s.margin;
    return s;
  }
  if (kind == "capsule") {
    col::Capsule s;
    in >> s.radius >> s.half_length >> s.margin;
    return s;
  }
  if (kind == "cylinder") {
    col::Cylinder s;
    in >> s.radius >> s.half_length >> s.margin;
    return s;
  }
  if (kind == "cone") {
    col::Cone s;
    in >> s.radius >> s.half_length >> s.margin;
    return s;
  }
  col::Polyhedron s;
  std::size_t n = 0;
  in >> s.margin >> n;
  std::vector<Eigen::Vector3d> points(n);
  for (Eigen::Vector3d& x : points) in >> x.x() >> x.y() >> x.z();
  s.hull = col::ConvexPolyhedron::build(points).polyhedron;
  return s;
}

Pose read_pose(std::istream& in) {
  Pose p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) in >> p.rotation(i, j);
  in >> p.translation.x() >> p.translation.y() >> p.translation.z();
  return p;
}

struct Case {
  std::string family;
  Shape a, b;
  Pose pose_a, pose_b;
  double exact = 0.0, exact_bound = 0.0, size = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  bool normal_unique = false;
};

#if defined(HEDRA_PROFILE_DUMP)
int dump(const std::string& file, const std::vector<std::string>& families) {
  std::ofstream out(file);
  for (const std::string& family : families) {
    const auto cases = hedra::tool::bench::make_family(family, {});
    std::cerr << family << ": " << cases.cases.size() << " pairs\n";
    for (const auto& c : cases.cases) {
      out << "case " << family << '\n';
      write_shape(out, c.a, c.points_a);
      write_pose(out, c.pose_a);
      write_shape(out, c.b, c.points_b);
      write_pose(out, c.pose_b);
      const auto& e = c.reference.exact;
      out << num(e.distance) << ' ' << num(e.error_bound) << ' ' << num(c.reference.pair_size) << ' '
          << num(e.normal.x()) << ' ' << num(e.normal.y()) << ' ' << num(e.normal.z()) << ' ' << e.normal_unique
          << '\n';
    }
  }
  return out ? 0 : 1;
}
#endif

std::vector<Case> load(const std::string& file, const std::string& only) {
  std::ifstream in(file);
  std::vector<Case> cases;
  std::string word;
  while (in >> word) {
    Case c;
    in >> c.family;
    c.a = read_shape(in);
    c.pose_a = read_pose(in);
    c.b = read_shape(in);
    c.pose_b = read_pose(in);
    in >> c.exact >> c.exact_bound >> c.size >> c.normal.x() >> c.normal.y() >> c.normal.z() >> c.normal_unique;
    if (only.empty() || c.family == only) cases.push_back(std::move(c));
  }
  return cases;
}

// Kept out of line (and the only caller of penetration() in the timed
// loop), so callgrind's toggle on penetration() sees the queries alone.
double sink = 0.0;

// The median over 7 loops of 200 calls of ns per call (--time).
template <class Call>
double median_ns_per_call(Call&& call) {
  std::vector<double> loops;
  for (int loop = 0; loop < 7; ++loop) {
    const int k = 200;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < k; ++i) sink += call();
    const auto t1 = std::chrono::steady_clock::now();
    loops.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / k);
  }
  std::nth_element(loops.begin(), loops.begin() + 3, loops.end());
  return loops[3];
}

int run(const std::string& file, const std::string& only, int repeat, bool time, const std::string& answers) {
  const std::vector<Case> cases = load(file, only);
  std::FILE* answers_out = answers.empty() ? nullptr : std::fopen(answers.c_str(), "w");
  if (!answers.empty() && !answers_out) {
    std::fprintf(stderr, "penetration_profile: cannot write %s\n", answers.c_str());
    return 2;
  }
  struct Stats {
    int queries = 0, failures = 0, gjk = 0, epa = 0, calls = 0, pairs = 0;
    double max_abs = 0.0, max_rel = 0.0;
    std::vector<double> ns;
  };
  std::map<std::string, Stats> stats;
  std::vector<std::string> order;
  std::uint64_t hash = 14695981039346656037ull;  // of every answer: same hash, same answers bit for bit
  for (const Case& c : cases) {
    if (!stats.count(c.family)) order.push_back(c.family);
    Stats& s = stats[c.family];
    col::PenetrationResult r;
    for (int k = 0; k < repeat; ++k) {
      r = col::penetration(c.a, c.pose_a, c.b, c.pose_b);
      sink += r.distance;
    }
    s.queries += repeat;
    ++s.pairs;
    s.gjk += r.gjk_iterations;
    s.epa += r.epa_iterations;
    s.calls += r.support_calls;
    const double err = std::abs(r.distance - c.exact);
    s.max_abs = std::max(s.max_abs, err);
    s.max_rel = std::max(s.max_rel, err / c.size);
    bool fail = !(err <= c.exact_bound + 1e-6 * c.size) || r.status == col::Status::max_iterations ||
                r.status == col::Status::polytope_full || r.status == col::Status::degenerate;
    if (c.normal_unique && std::abs(c.exact) > 0.0) {
      const double angle = std::atan2(r.normal.cross(c.normal).norm(), r.normal.dot(c.normal));
      if (!(angle <= 1e-3)) fail = true;
    }
    for (const double x : {r.distance, r.normal.x(), r.normal.y(), r.normal.z(), r.point_a.x(), r.point_b.z()}) {
      std::uint64_t bits;
      std::memcpy(&bits, &x, sizeof bits);
      hash = (hash ^ bits) * 1099511628211ull;
    }
    if (answers_out)
      std::fprintf(answers_out,
                   "%s %d %s %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                   c.family.c_str(), s.pairs - 1, col::to_string(r.status), r.distance, r.error_bound, r.normal.x(),
                   r.normal.y(), r.normal.z(), r.point_a.x(), r.point_a.y(), r.point_a.z(), r.point_b.x(),
                   r.point_b.y(), r.point_b.z(), c.exact, c.exact_bound, c.size);
    if (fail) {
      ++s.failures;
      std::fprintf(stderr, "FAIL %s: got %.17g (%s), exact %.17g\n", c.family.c_str(), r.distance,
                   col::to_string(r.status), c.exact);
    }
    if (time)
      s.ns.push_back(median_ns_per_call([&] { return col::penetration(c.a, c.pose_a, c.b, c.pose_b).distance; }));
  }
  int failures = 0;
  for (const std::string& f : order) {
    Stats& s = stats[f];
    failures += s.failures;
    std::printf("%-18s pairs %4d queries %6d failures %d max_abs %.3g max_rel %.3g gjk %.2f epa %.2f calls %.2f",
                f.c_str(), s.pairs, s.queries, s.failures, s.max_abs, s.max_rel, double(s.gjk) / s.pairs,
                double(s.epa) / s.pairs, double(s.calls) / s.pairs);
    if (time && !s.ns.empty()) {
      std::nth_element(s.ns.begin(), s.ns.begin() + s.ns.size() / 2, s.ns.end());
      std::printf(" median_ns %.0f", s.ns[s.ns.size() / 2]);
    }
    std::printf("\n");
  }
  std::printf("answers hash %016llx\n", static_cast<unsigned long long>(hash));
  if (answers_out) std::fclose(answers_out);
  return failures == 0 ? 0 : 1;
}

// --query distance | intersect: the same replay for distance() or intersect().
int run_query(const std::string& file, const std::string& only, int repeat, bool time, bool distance) {
  struct Stats {
    int queries = 0, failures = 0, iterations = 0, calls = 0, pairs = 0, skipped = 0;
    double max_abs = 0.0, max_rel = 0.0;
    std::vector<double> ns;
  };
  std::map<std::string, Stats> stats;
  std::vector<std::string> order;
  std::uint64_t hash = 14695981039346656037ull;
  const auto mix = [&hash](double x) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    hash = (hash ^ bits) * 1099511628211ull;
  };
  for (const Case& c : load(file, only)) {
    if (!stats.count(c.family)) order.push_back(c.family);
    Stats& s = stats[c.family];
    const double tolerance = c.exact_bound + 1e-6 * c.size;
    if (distance && !(c.exact > tolerance)) {
      ++s.skipped;
      continue;
    }
    bool fail = false;
    if (distance) {
      col::DistanceResult r;
      for (int k = 0; k < repeat; ++k) {
        r = col::distance(c.a, c.pose_a, c.b, c.pose_b);
        sink += r.distance;
      }
      s.iterations += r.iterations;
      s.calls += r.support_calls;
      const double err = std::abs(r.distance - c.exact);
      s.max_abs = std::max(s.max_abs, err);
      s.max_rel = std::max(s.max_rel, err / c.size);
      fail = r.intersecting || !(err <= tolerance) || r.status == col::Status::max_iterations ||
             r.status == col::Status::degenerate;
      if (c.normal_unique && !(std::atan2(r.normal.cross(c.normal).norm(), r.normal.dot(c.normal)) <= 1e-3))
        fail = true;
      for (const double x : {r.distance, r.normal.x(), r.normal.y(), r.normal.z(), r.point_a.x(), r.point_b.z()})
        mix(x);
    } else {
      col::IntersectResult r;
      for (int k = 0; k < repeat; ++k) {
        r = col::intersect(c.a, c.pose_a, c.b, c.pose_b);
        sink += r.intersecting ? 1.0 : 0.0;
      }
      s.iterations += r.iterations;
      s.calls += r.support_calls;
      fail = r.status != col::Status::ok || (std::abs(c.exact) > tolerance && r.intersecting != (c.exact < 0));
      mix(r.intersecting ? 1.0 : 0.0);
      mix(static_cast<double>(r.status));
    }
    s.queries += repeat;
    ++s.pairs;
    if (fail) {
      ++s.failures;
      std::fprintf(stderr, "FAIL %s %d: exact %.17g\n", c.family.c_str(), s.pairs - 1, c.exact);
    }
    if (time)
      s.ns.push_back(median_ns_per_call([&] {
        return distance ? col::distance(c.a, c.pose_a, c.b, c.pose_b).distance
                        : (col::intersect(c.a, c.pose_a, c.b, c.pose_b).intersecting ? 1.0 : 0.0);
      }));
  }
  int failures = 0;
  for (const std::string& f : order) {
    Stats& s = stats[f];
    failures += s.failures;
    std::printf("%-18s pairs %4d queries %6d failures %d max_abs %.3g max_rel %.3g gjk %.2f calls %.2f skipped %d",
                f.c_str(), s.pairs, s.queries, s.failures, s.max_abs, s.max_rel,
                s.pairs ? double(s.iterations) / s.pairs : 0.0, s.pairs ? double(s.calls) / s.pairs : 0.0, s.skipped);
    if (time && !s.ns.empty()) {
      std::nth_element(s.ns.begin(), s.ns.begin() + s.ns.size() / 2, s.ns.end());
      std::printf(" median_ns %.0f", s.ns[s.ns.size() / 2]);
    }
    std::printf("\n");
  }
  std::printf("answers hash %016llx\n", static_cast<unsigned long long>(hash));
  return failures == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
#if defined(HEDRA_PROFILE_DUMP)
  if (argc >= 4 && std::strcmp(argv[1], "dump") == 0) return dump(argv[2], {argv + 3, argv + argc});
#endif
  if (argc >= 3 && std::strcmp(argv[1], "run") == 0) {
    std::string only;
    int repeat = 1;
    bool time = false;
    std::string answers, query = "penetration";
    for (int i = 3; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg == "--family" && i + 1 < argc)
        only = argv[++i];
      else if (arg == "--repeat" && i + 1 < argc)
        repeat = std::max(1, std::atoi(argv[++i]));
      else if (arg == "--time")
        time = true;
      else if (arg == "--answers" && i + 1 < argc)
        answers = argv[++i];
      else if (arg == "--query" && i + 1 < argc)
        query = argv[++i];
    }
    if (query == "distance" || query == "intersect") return run_query(argv[2], only, repeat, time, query == "distance");
    if (query != "penetration") {
      std::fprintf(stderr, "penetration_profile: --query: penetration, distance or intersect\n");
      return 2;
    }
    return run(argv[2], only, repeat, time, answers);
  }
  std::fprintf(
      stderr,
      "usage: penetration_profile dump FILE FAMILY... | run FILE [--family NAME] [--repeat N] [--time] [--answers OUT] "
      "[--query penetration|distance|intersect]\n");
  return 2;
}
