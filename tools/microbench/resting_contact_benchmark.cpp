// The resting-contact hot path beside Bullet's own narrowphase: B resting on
// A (1 mm overlap, yawed 0.3 rad), still (a solver's corrections: 1e-6 of
// the size a frame), sliding and turning (1 % of the size and 0.01 rad a
// frame, back and forth), or settling (rocking on an edge, 0.05 rad
// decaying to flat), every frame placed by penetration() (outside any
// timing). Pairs: hull on hull (slab hulls: points on an ellipsoid with a
// flat top and bottom, 8 to 1,000 points; equal_hull: B a copy of A, its
// corners over A's rim), hull on box, box on hull, rounded
// (margin 0.05), and spheres, capsules (lying) and cylinders (standing) on
// boxes and hulls. No box-box pair: those have their own detector.
//
// Per family and motion: hedra's contact() cold (no cache) and warm (the
// pair's ContactCache carried from frame to frame) beside the algorithm
// Bullet 3.24 (double) picks for the pair under its default dispatcher
// (btConvexConvexAlgorithm, btSphereBoxCollisionAlgorithm, ...), run as its
// world runs it (processCollision into the pair's persistent manifold,
// kept: warm), on plain shapes and with initializePolyhedralFeatures() on
// boxes and hulls (Bullet's face clipping). CPU ns per query: the median
// over `repetitions` passes over every frame of every pair, frame-major.
// Checks: cache hits, the largest |warm - cold| distance over the size where
// both took the same path, and the frames with another path.
//
// Run: build/bin/resting_contact_benchmark [pairs=8] [frames=200] [repetitions=5] [family-prefix]
// Instructions per call (callgrind): add `--callgrind MODE` (MODE: cold,
// warm, bullet, bullet_polyhedral) and one family, and run under
//   valgrind --tool=callgrind --toggle-collect='*timed_query*' build/bin/resting_contact_benchmark ...
// (the program prints the number of calls; Ir / calls is the figure).
// `--answers FILE` writes every cold answer instead of timing (two builds'
// files, compared, show which answers moved).
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <hedra/collision/manifold.hpp>
#include <random>
#include <string>
#include <vector>

#include "bullet_dispatch.hpp"
#include "trajectories.hpp"

namespace {

using namespace hedra::collision;
using hedra::trajectories::Trajectory;
using Vec = Eigen::Vector3d;

double cpu_ns() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return 1e9 * static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec);
}

// A hull of n points on the ellipsoid `radii` with z clamped to +-flat:
// flat top and bottom faces (polygons), curved sides.
Polyhedron slab_hull(std::mt19937_64& rng, int n, const Vec& radii, double flat, double margin) {
  std::vector<Vec> points;
  for (int i = 0; i < n; ++i) {
    Vec p = hedra::trajectories::random_unit(rng).cwiseProduct(radii);
    p.z() = std::clamp(p.z(), -flat, flat);
    points.push_back(p);
  }
  Polyhedron poly{ConvexPolyhedron::build(points).polyhedron};
  poly.margin = margin;
  return poly;
}

struct Family {
  std::string name;
  Shape a, b;
  Pose b_rest;  // B's orientation at rest (rotation only)
};

// The family's pair for seed i: A below, B on its top face.
Family make_family(const std::string& name, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const double margin = name.find("rounded") != std::string::npos ? 0.05 : 0.0;
  const auto number = [&](const std::string& s) {
    const std::size_t k = s.find_first_of("0123456789");
    return k == std::string::npos ? 24 : std::atoi(s.c_str() + k);
  };
  Family f;
  f.name = name;
  const Box plate{Vec(1.0, 1.0, 0.25), margin};
  std::string base = name.substr(0, name.find('/'));
  if (base.rfind("rounded_", 0) == 0) base = base.substr(8);  // the margin is set above
  if (base.rfind("sphere", 0) == 0 || base.rfind("capsule", 0) == 0 || base.rfind("cylinder", 0) == 0) {
    f.a = base.find("_box") != std::string::npos ? Shape(plate)
                                                 : Shape(slab_hull(rng, 200, Vec(1.0, 0.9, 1.0), 0.3, margin));
    if (base.rfind("sphere", 0) == 0) f.b = Sphere{0.25, 0.0};
    if (base.rfind("capsule", 0) == 0) {
      f.b = Capsule{0.15, 0.35, 0.0};
      f.b_rest.rotation = Eigen::AngleAxisd(M_PI / 2, Vec::UnitY()).toRotationMatrix();  // lying
    }
    if (base.rfind("cylinder", 0) == 0) f.b = Cylinder{0.25, 0.2, 0.0};  // standing on its cap
  } else if (base.rfind("box_hull", 0) == 0) {                           // a hull on a box
    f.a = plate;
    f.b = slab_hull(rng, number(base), Vec(0.6, 0.5, 0.6), 0.2, margin);
  } else if (base.rfind("hull_box", 0) == 0) {  // a box on a hull
    f.a = slab_hull(rng, number(base), Vec(1.0, 0.9, 1.0), 0.3, margin);
    f.b = Box{Vec(0.3, 0.25, 0.2), margin};
  } else if (base.rfind("equal_hull", 0) == 0) {  // two hulls of one shape, B's corners over A's rim
    f.a = slab_hull(rng, number(base), Vec(1.0, 0.9, 1.0), 0.3, margin);
    f.b = f.a;
  } else {  // hull on hull
    f.a = slab_hull(rng, number(base), Vec(1.0, 0.9, 1.0), 0.3, margin);
    f.b = slab_hull(rng, number(base), Vec(0.6, 0.5, 0.6), 0.2, margin);
  }
  f.b_rest.rotation = Eigen::AngleAxisd(0.3, Vec::UnitZ()).toRotationMatrix() * f.b_rest.rotation;
  return f;
}

// Frames of B on A for one motion: still, sliding, settling.
Trajectory make_motion(const Family& f, const std::string& motion, int frames, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Trajectory t;
  t.a = f.a;
  t.b = f.b;
  t.size = bounding_radius(f.a) + bounding_radius(f.b);
  const double overlap = -1e-3;
  Pose pose = f.b_rest;
  pose.translation = Vec(0.0, 0.0, 2.0);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int k = 0; k < frames; ++k) {
    if (motion == "still") {
      if (k > 0) {  // a solver's corrections
        pose.rotation =
            Eigen::AngleAxisd(1e-6, hedra::trajectories::random_unit(rng)).toRotationMatrix() * pose.rotation;
        pose.translation += 1e-6 * t.size * Vec(g(rng), g(rng), 0.0);
      }
    } else if (motion == "sliding") {
      const double sign = (k / 50) % 2 == 0 ? 1.0 : -1.0;
      pose.translation += sign * 0.01 * t.size * Vec(1.0, 0.3, 0.0).normalized();
      pose.rotation = Eigen::AngleAxisd(0.01, Vec::UnitZ()).toRotationMatrix() * pose.rotation;
    } else {  // settling: rocking about a horizontal axis, decaying to flat
      const double tilt = 0.05 * std::pow(0.97, k) * std::cos(0.3 * k);
      pose.rotation = Eigen::AngleAxisd(tilt, Vec(1.0, 0.5, 0.0).normalized()).toRotationMatrix() * f.b_rest.rotation;
    }
    hedra::trajectories::place(t, pose, overlap);
    t.pose_b.push_back(pose);
  }
  return t;
}

// The timed calls, named for callgrind's --toggle-collect.
__attribute__((noinline)) ContactResult timed_query_hedra(const Trajectory& t, int f, ContactCache* cache) {
  return contact(t.a, t.pose_a, t.b, t.pose_b[f], cache);
}
__attribute__((noinline)) hedra::peers::DispatchAnswer timed_query_bullet(hedra::peers::DispatchedPair& p,
                                                                          const Trajectory& t, int f, bool warm) {
  return p.query(t.pose_a, t.pose_b[f], warm);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Median CPU ns per query over the repetitions; run(pair, frame).
template <class Run>
double time_per_query(std::size_t pairs, int frames, int repetitions, Run run) {
  std::vector<double> times;
  for (int r = 0; r < repetitions; ++r) {
    const double start = cpu_ns();
    for (int f = 0; f < frames; ++f)
      for (std::size_t i = 0; i < pairs; ++i) run(i, f);
    times.push_back((cpu_ns() - start) / (static_cast<double>(frames) * static_cast<double>(pairs)));
  }
  return median(times);
}

struct Row {
  double cold = 0, warm = 0, bullet_cold = 0, bullet_warm = 0, poly_cold = 0, poly_warm = 0;
  double hits = 0, max_diff = 0;
  int other_path = 0;
  std::string algorithm;
};

// Every cold answer of the family, one line a frame (--answers FILE): two
// builds' files compared line by line show which answers moved and by how
// much.
void write_answers(std::FILE* out, const std::string& name, const std::string& motion,
                   const std::vector<Trajectory>& ts, int frames) {
  for (std::size_t i = 0; i < ts.size(); ++i)
    for (int f = 0; f < frames; ++f) {
      const ContactResult r = contact(ts[i].a, ts[i].pose_a, ts[i].b, ts[i].pose_b[f]);
      std::fprintf(out, "%s/%s %zu %d %s %s %d %.17g %.17g %.17g %.17g %.17g", name.c_str(), motion.c_str(), i, f,
                   to_string(r.status), to_string(r.path), r.count, ts[i].size, r.distance, r.normal.x(), r.normal.y(),
                   r.normal.z());
      for (int k = 0; k < r.count; ++k)
        std::fprintf(out, " %.17g %.17g %.17g %.17g", r.points[k].point.x(), r.points[k].point.y(),
                     r.points[k].point.z(), r.points[k].depth);
      std::fprintf(out, "\n");
    }
}

std::FILE* g_answers = nullptr;

void run_family(const std::string& name, const std::string& motion, int pairs, int frames, int repetitions,
                const std::string& callgrind) {
  std::vector<Trajectory> ts;
  std::vector<std::unique_ptr<hedra::peers::DispatchedPair>> bullet, bullet_poly;
  for (int i = 0; i < pairs; ++i) {
    const Family f = make_family(name, 1000 + static_cast<std::uint64_t>(i));
    ts.push_back(make_motion(f, motion, frames, 2000 + static_cast<std::uint64_t>(i)));
    bullet.push_back(hedra::peers::prepare_bullet_dispatch(f.a, f.b, false));
    bullet_poly.push_back(hedra::peers::prepare_bullet_dispatch(f.a, f.b, true));
  }
  const std::size_t n = ts.size();
  std::vector<ContactCache> caches(n);
  if (g_answers) {
    write_answers(g_answers, name, motion, ts, frames);
    return;
  }
  if (!callgrind.empty()) {
    long calls = 0;
    for (int f = 0; f < frames; ++f)
      for (std::size_t i = 0; i < n; ++i, ++calls) {
        if (callgrind == "cold") timed_query_hedra(ts[i], f, nullptr);
        if (callgrind == "warm") timed_query_hedra(ts[i], f, &caches[i]);
        if (callgrind == "bullet" && bullet[i]) timed_query_bullet(*bullet[i], ts[i], f, true);
        if (callgrind == "bullet_polyhedral" && bullet_poly[i]) timed_query_bullet(*bullet_poly[i], ts[i], f, true);
      }
    std::printf("%s/%s %s: %ld calls\n", name.c_str(), motion.c_str(), callgrind.c_str(), calls);
    return;
  }
  Row row;
  // Answers: cold and warm, compared frame by frame.
  long hit = 0, total = 0;
  for (int f = 0; f < frames; ++f)
    for (std::size_t i = 0; i < n; ++i) {
      const ContactResult cold = contact(ts[i].a, ts[i].pose_a, ts[i].b, ts[i].pose_b[f]);
      const ContactResult warm = contact(ts[i].a, ts[i].pose_a, ts[i].b, ts[i].pose_b[f], &caches[i]);
      hit += warm.stats.cache_hit ? 1 : 0;
      ++total;
      if (cold.path != warm.path)
        ++row.other_path;
      else if (cold.path != ContactPath::separated)
        row.max_diff = std::max(row.max_diff, std::abs(cold.distance - warm.distance) / ts[i].size);
    }
  row.hits = static_cast<double>(hit) / static_cast<double>(total);
  volatile double sink = 0;
  row.cold = time_per_query(n, frames, repetitions,
                            [&](std::size_t i, int f) { sink = sink + timed_query_hedra(ts[i], f, nullptr).distance; });
  for (auto& c : caches) c = ContactCache{};
  row.warm = time_per_query(n, frames, repetitions, [&](std::size_t i, int f) {
    sink = sink + timed_query_hedra(ts[i], f, &caches[i]).distance;
  });
  if (bullet[0]) {
    row.bullet_cold = time_per_query(n, frames, repetitions, [&](std::size_t i, int f) {
      sink = sink + timed_query_bullet(*bullet[i], ts[i], f, false).points;
    });
    row.bullet_warm = time_per_query(n, frames, repetitions, [&](std::size_t i, int f) {
      sink = sink + timed_query_bullet(*bullet[i], ts[i], f, true).points;
    });
    row.poly_cold = time_per_query(n, frames, repetitions, [&](std::size_t i, int f) {
      sink = sink + timed_query_bullet(*bullet_poly[i], ts[i], f, false).points;
    });
    row.poly_warm = time_per_query(n, frames, repetitions, [&](std::size_t i, int f) {
      sink = sink + timed_query_bullet(*bullet_poly[i], ts[i], f, true).points;
    });
    row.algorithm = bullet[0]->algorithm();
  }
  const double best_bullet = std::min(row.bullet_warm, row.poly_warm);
  std::printf("| %s | %s | %.0f | %.0f | %.2f | %.0f %% | %.0f / %.0f | %.0f / %.0f | %.2f | %s | %.1e | %d |\n",
              name.c_str(), motion.c_str(), row.cold, row.warm, row.cold / row.warm, 100.0 * row.hits, row.bullet_cold,
              row.bullet_warm, row.poly_cold, row.poly_warm, row.warm / best_bullet, row.algorithm.c_str(),
              row.max_diff, row.other_path);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args;
  std::string callgrind;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--callgrind") == 0 && i + 1 < argc) {
      callgrind = argv[++i];
      continue;
    }
    if (std::strcmp(argv[i], "--answers") == 0 && i + 1 < argc) {
      g_answers = std::fopen(argv[++i], "w");
      if (!g_answers) {
        std::fprintf(stderr, "resting_contact_benchmark: cannot write %s\n", argv[i]);
        return 2;
      }
      continue;
    }
    args.push_back(argv[i]);
  }
  const int pairs = args.size() > 0 ? std::atoi(args[0].c_str()) : 8;
  const int frames = args.size() > 1 ? std::atoi(args[1].c_str()) : 200;
  const int repetitions = args.size() > 2 ? std::atoi(args[2].c_str()) : 5;
  const std::string only = args.size() > 3 ? args[3] : "";
  if (pairs < 1 || frames < 1 || repetitions < 1) {
    std::fprintf(stderr,
                 "usage: resting_contact_benchmark [pairs>=1] [frames>=1] [repetitions>=1] [family-prefix] "
                 "[--callgrind cold|warm|bullet|bullet_polyhedral]\n");
    return 2;
  }
  const char* families[] = {"hull8",          "hull24",      "equal_hull24", "hull200",      "hull1000",
                            "rounded_hull24", "box_hull24",  "box_hull200",  "hull_box200",  "rounded_box_hull24",
                            "sphere_box",     "sphere_hull", "capsule_box",  "capsule_hull", "cylinder_box",
                            "cylinder_hull"};
  const char* motions[] = {"still", "sliding", "settling"};
  if (callgrind.empty() && !g_answers)
    std::printf(
        "| pair (B on A) | motion | hedra cold ns | warm ns | cold/warm | cache hits | Bullet cold / warm ns | "
        "Bullet polyhedral cold / warm ns | hedra warm / best Bullet warm | Bullet's algorithm | max abs(warm - cold) "
        "/ size | frames on another path |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const char* family : families) {
    const std::string only_family = only.substr(0, only.find('/'));
    if (only.find('/') != std::string::npos ? only_family != family : std::string(family).rfind(only, 0) != 0) continue;
    for (const char* motion : motions) {
      const std::string want = only.find('/') != std::string::npos ? only.substr(only.find('/') + 1) : "";
      if (!want.empty() && want != motion) continue;
      run_family(family, motion, pairs, frames, repetitions, callgrind);
    }
  }
  if (g_answers) std::fclose(g_answers);
  return 0;
}
