// Frame coherence: penetration() and contact() on pairs moving along smooth
// trajectories (trajectories.hpp: 1 % of the size and 1 degree a frame;
// separated, touching and slightly penetrating; boxes, a box resting and
// sliding on a plate, hulls of 8 to 1,000 vertices, rounded boxes and hulls),
// each cold (no cache) and warm (the pair's GjkCache / ContactCache carried
// from frame to frame), beside Bullet's btGjkPairDetector kept per pair with
// its cached separating axis (warm) or reset each frame (cold), under
// HEDRA_WITH_PEERS.
//
// Per family: CPU time per query (ns, the best of `repetitions` passes over
// every frame of every pair, frame-major so each cache sees its pair's last
// frame), and the warm answers checked against the cold ones: the largest
// |warm - cold| signed distance over the size for penetration(), and for
// contact() the largest distance difference where both took the same path
// (separated answers aside: a lower bound either way), the frames with
// another path (ties: two axes within the bias, which the start of a
// support's climb decides), and the frames where the cache kept B's
// reference face where a cold query takes another axis (by design, within
// the bias).
//
// Run: build/bin/coherence_benchmark [pairs=16] [frames=200] [repetitions=3] [family]
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <hedra/collision/manifold.hpp>
#include <string>
#include <vector>

#include "trajectories.hpp"
#ifdef HEDRA_WITH_PEERS
#  include "bullet_manifold.hpp"
#endif

namespace {

using namespace hedra::collision;
using hedra::trajectories::Trajectory;

double cpu_ns() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return 1e9 * static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec);
}

// Best time per query over the repetitions; `run(pair, frame, first)` does
// one query (first: the first frame of a pass, when caches reset).
template <class Run>
double time_per_query(const std::vector<Trajectory>& ts, int repetitions, Run run) {
  const int frames = static_cast<int>(ts[0].pose_b.size());
  double best = INFINITY;
  for (int r = 0; r < repetitions; ++r) {
    const double start = cpu_ns();
    for (int f = 0; f < frames; ++f)
      for (std::size_t i = 0; i < ts.size(); ++i) run(i, f, f == 0);
    best = std::min(best, (cpu_ns() - start) / (static_cast<double>(frames) * static_cast<double>(ts.size())));
  }
  return best;
}

struct Agreement {
  double penetration = 0.0;  // max |warm - cold| / size
  double contact = 0.0;      // the same, where both took the same path
  int kept_b = 0;            // frames where the cache kept B's face as the reference
  int ties = 0;              // frames with another path (another axis within the bias)
  int frames = 0;
  int hits = 0;  // warm frames answered from the cached axis
};

Agreement compare(const std::vector<Trajectory>& ts) {
  Agreement a;
  for (const Trajectory& t : ts) {
    GjkCache gjk;
    ContactCache cc;
    for (const Pose& pb : t.pose_b) {
      const PenetrationResult pc = penetration(t.a, t.pose_a, t.b, pb);
      const PenetrationResult pw = penetration(t.a, t.pose_a, t.b, pb, &gjk);
      a.penetration = std::max(a.penetration, std::abs(pc.distance - pw.distance) / t.size);
      const ContactResult cc0 = contact(t.a, t.pose_a, t.b, pb);
      const ContactCache before = cc;
      const ContactResult cw = contact(t.a, t.pose_a, t.b, pb, &cc);
      ++a.frames;
      a.hits += cw.stats.cache_hit;
      if (cw.path == ContactPath::separated) continue;  // a lower bound either way
      // B's face kept by the cache where a cold query takes another axis:
      // by design (within the bias).
      if (before.axis == SatAxisKind::face_b && cw.path == ContactPath::face_b && cc0.path != ContactPath::face_b &&
          cw.count > 0 && cw.points[0].id.reference == before.feature) {
        ++a.kept_b;
        continue;
      }
      if (cc0.path != cw.path) {
        ++a.ties;
        continue;
      }
      a.contact = std::max(a.contact, std::abs(cc0.distance - cw.distance) / t.size);
    }
  }
  return a;
}

void run_family(const std::string& shape, const char* kind, double target, int pairs, int frames, int repetitions) {
  const std::vector<Trajectory> ts = hedra::trajectories::make_trajectories(shape, target, pairs, frames, 2026);
  std::vector<GjkCache> gjk(ts.size());
  std::vector<ContactCache> cc(ts.size());
  const double pen_cold = time_per_query(ts, repetitions, [&](std::size_t i, int f, bool) {
    const PenetrationResult r = penetration(ts[i].a, ts[i].pose_a, ts[i].b, ts[i].pose_b[f]);
    asm volatile("" : : "r"(&r) : "memory");
  });
  const double pen_warm = time_per_query(ts, repetitions, [&](std::size_t i, int f, bool first) {
    if (first) gjk[i] = GjkCache{};
    const PenetrationResult r = penetration(ts[i].a, ts[i].pose_a, ts[i].b, ts[i].pose_b[f], &gjk[i]);
    asm volatile("" : : "r"(&r) : "memory");
  });
  const double con_cold = time_per_query(ts, repetitions, [&](std::size_t i, int f, bool) {
    const ContactResult r = contact(ts[i].a, ts[i].pose_a, ts[i].b, ts[i].pose_b[f]);
    asm volatile("" : : "r"(&r) : "memory");
  });
  const double con_warm = time_per_query(ts, repetitions, [&](std::size_t i, int f, bool first) {
    if (first) cc[i] = ContactCache{};
    const ContactResult r = contact(ts[i].a, ts[i].pose_a, ts[i].b, ts[i].pose_b[f], &cc[i]);
    asm volatile("" : : "r"(&r) : "memory");
  });
  double bullet_cold = NAN, bullet_warm = NAN;
#ifdef HEDRA_WITH_PEERS
  std::vector<std::unique_ptr<hedra::peers::MovingPair>> bullet;
  for (const Trajectory& t : ts) bullet.push_back(hedra::peers::prepare_bullet_moving(t.a, t.b, true));
  if (bullet[0]) {
    bullet_cold = time_per_query(ts, repetitions, [&](std::size_t i, int f, bool) {
      const hedra::peers::PeerResult r = bullet[i]->query(ts[i].pose_a, ts[i].pose_b[f], false);
      asm volatile("" : : "r"(&r) : "memory");
    });
    bullet_warm = time_per_query(ts, repetitions, [&](std::size_t i, int f, bool) {
      const hedra::peers::PeerResult r = bullet[i]->query(ts[i].pose_a, ts[i].pose_b[f], true);
      asm volatile("" : : "r"(&r) : "memory");
    });
  }
#endif
  const Agreement a = compare(ts);
  std::printf(
      "| %s | %s | %.0f | %.0f | %.2f | %.0f | %.0f | %.2f | %.0f %% | %.0f | %.0f | %.2g | %.2g | %d / %d / %d |\n",
      shape.c_str(), kind, pen_cold, pen_warm, pen_cold / pen_warm, con_cold, con_warm, con_cold / con_warm,
      100.0 * a.hits / std::max(a.frames, 1), bullet_cold, bullet_warm, a.penetration, a.contact, a.ties, a.kept_b,
      a.frames);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const int pairs = argc > 1 ? std::atoi(argv[1]) : 16;
  const int frames = argc > 2 ? std::atoi(argv[2]) : 200;
  const int repetitions = argc > 3 ? std::atoi(argv[3]) : 3;
  const std::string only = argc > 4 ? argv[4] : "";
  std::printf(
      "| family | kind | penetration cold ns | warm ns | cold/warm | contact cold ns | warm ns | cold/warm | "
      "warm from the cache | Bullet GJK cold ns | warm ns | max abs(warm - cold) / size: penetration | contact | "
      "contact ties / B's face kept / frames |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  const char* shapes[] = {"box",     "box_resting", "hull8",       "hull32",
                          "hull128", "hull1000",    "rounded_box", "rounded_hull32"};
  for (const char* shape : shapes) {
    if (!only.empty() && only != shape) continue;
    run_family(shape, "separated", 0.02, pairs, frames, repetitions);
    run_family(shape, "touching", 0.0, pairs, frames, repetitions);
    run_family(shape, "penetrating", -0.01, pairs, frames, repetitions);
  }
  return 0;
}
