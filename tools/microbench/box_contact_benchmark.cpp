// Box pairs on the resting-contact hot path: hedra's contact() cold and with
// its per-pair ContactCache, beside Bullet 3.24 double's btBoxBoxDetector
// (ODE's box-box, constructed anew for every call as btBoxBoxCollisionAlgorithm
// does), on the same frames in one run.
//
// Families (B on A; A a unit box at the origin, B yawed 0.3 rad about z):
//   unit      unit boxes                 plates    1 cm plates (1 x 1 x 0.01)
//   small     a 2 cm box on a unit box   rounded   unit boxes, margin 0.05
// Depths: 1 mm and 1 cm overlap, 1 mm apart (contact_distance 2 mm: the
// speculative points a solver wants; Bullet's detector reports none apart).
// Motions over 1000 frames: still (the same poses every frame), jitter
// (B moved by 1e-6 of the size a frame, as a solver's corrections move a
// resting body), slide (1 mm a frame along x), turn (2 mrad a frame about z).
// Rounded boxes: Bullet has none; its row is the sharp box of the rounded
// box's outer size (half extents + margin), a yardstick only.
//
// Each repeat times, per family, the 1000 frames cold (no cache), warm (one
// cache carried across the frames), the same two on the general polytope
// path (ContactSettings::box_box_path = false: what box pairs took before
// box_box.cpp) and Bullet, interleaved; the table (markdown) gives the
// medians over the repeats of ns per call and of the ratios taken within
// each repeat (cold / Bullet, warm / cold), and the warm cache's hit rate.
//
// Run:   build/bin/box_contact_benchmark [--repeats 9] [--filter SUBSTRING]
// Count: `--once NAME MODE` runs one family's 1000 frames in one mode (cold,
//        warm, bullet, general-cold, general-warm, none); callgrind's total
//        less the `none` run's, divided by 1000, is the instructions per call
//        (box_contact_instructions.sh runs them).
// Check: `--verify 200000` compares the box path with the general path on
//        200,000 random pairs (see verify()); exit 1 on a mismatch.
#include <BulletCollision/CollisionDispatch/btBoxBoxDetector.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <hedra/collision/manifold.hpp>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace hedra::collision;
using Vec = Eigen::Vector3d;

struct Family {
  std::string name;
  Box a, b;
  double contact_distance = 0.0;
  std::vector<Pose> pose_a, pose_b;
};

Pose yawed(double yaw, const Vec& t) { return {Eigen::AngleAxisd(yaw, Vec::UnitZ()).toRotationMatrix(), t}; }

constexpr int kFrames = 1000;

std::vector<Family> make_families() {
  struct Size {
    const char* name;
    Vec ha, hb;
    double margin;
  };
  const Size sizes[] = {{"unit", Vec(0.5, 0.5, 0.5), Vec(0.5, 0.5, 0.5), 0.0},
                        {"plates", Vec(0.5, 0.5, 0.005), Vec(0.5, 0.5, 0.005), 0.0},
                        {"small", Vec(0.5, 0.5, 0.5), Vec(0.01, 0.01, 0.01), 0.0},
                        {"rounded", Vec(0.45, 0.45, 0.45), Vec(0.45, 0.45, 0.45), 0.05}};
  struct Depth {
    const char* name;
    double overlap;
  };
  const Depth depths[] = {{"1mm", 1e-3}, {"1cm", 1e-2}, {"apart1mm", -1e-3}};
  const char* motions[] = {"still", "jitter", "slide", "turn"};
  std::vector<Family> out;
  for (const Size& s : sizes)
    for (const Depth& d : depths)
      for (const char* m : motions) {
        // Plates: 0.1 mm for the small overlap (a 1 cm plate).
        double overlap = d.overlap;
        if (std::string(s.name) == "plates" && overlap == 1e-3) overlap = 1e-4;
        if (std::string(s.name) == "plates" && overlap == 1e-2) overlap = 1e-3;
        Family f;
        f.name = std::string(s.name) + "/" + d.name + "/" + m;
        f.a.half_extents = s.ha;
        f.a.margin = s.margin;
        f.b.half_extents = s.hb;
        f.b.margin = s.margin;
        f.contact_distance = overlap < 0.0 ? 2e-3 : 0.0;
        const double z = s.ha.z() + s.hb.z() + 2.0 * s.margin - overlap;
        const double size = std::max(s.ha.maxCoeff(), s.hb.maxCoeff()) + s.margin;
        unsigned state = 12345;
        const auto noise = [&] {
          state = state * 1664525u + 1013904223u;
          return (static_cast<double>(state >> 8) / 16777216.0 - 0.5) * 2e-6 * size;
        };
        Vec t(0.05, -0.03, z);
        double yaw = 0.3;
        for (int k = 0; k < kFrames; ++k) {
          const std::string motion = m;
          if (motion == "jitter") t = Vec(0.05, -0.03, z) + Vec(noise(), noise(), noise());
          if (motion == "slide") t.x() = 0.05 - 0.25 + 0.5 * k / kFrames;
          if (motion == "turn") yaw = 0.3 + 0.002 * k;
          f.pose_a.push_back(Pose::identity());
          f.pose_b.push_back(yawed(yaw, t));
        }
        out.push_back(std::move(f));
      }
  return out;
}

// Bullet's result: the points it reports (the count, and a sum so nothing is
// optimised away).
struct CountingResult : btDiscreteCollisionDetectorInterface::Result {
  int points = 0;
  double sum = 0.0;
  void setShapeIdentifiersA(int, int) override {}
  void setShapeIdentifiersB(int, int) override {}
  void addContactPoint(const btVector3& normal, const btVector3& point, btScalar depth) override {
    ++points;
    sum += depth + normal.x() + point.z();
  }
};

btTransform to_bullet(const Pose& p) {
  btMatrix3x3 m(p.rotation(0, 0), p.rotation(0, 1), p.rotation(0, 2), p.rotation(1, 0), p.rotation(1, 1),
                p.rotation(1, 2), p.rotation(2, 0), p.rotation(2, 1), p.rotation(2, 2));
  return btTransform(m, btVector3(p.translation.x(), p.translation.y(), p.translation.z()));
}

struct BulletFamily {
  std::unique_ptr<btBoxShape> a, b;
  std::vector<btTransform> ta, tb;
};

BulletFamily bullet_family(const Family& f) {
  BulletFamily out;
  const Vec ha = f.a.half_extents + Vec::Constant(f.a.margin), hb = f.b.half_extents + Vec::Constant(f.b.margin);
  out.a = std::make_unique<btBoxShape>(btVector3(ha.x(), ha.y(), ha.z()));
  out.b = std::make_unique<btBoxShape>(btVector3(hb.x(), hb.y(), hb.z()));
  out.a->setMargin(0.0);  // btBoxBoxDetector uses the half extents with the margin
  out.b->setMargin(0.0);
  for (std::size_t k = 0; k < f.pose_a.size(); ++k) {
    out.ta.push_back(to_bullet(f.pose_a[k]));
    out.tb.push_back(to_bullet(f.pose_b[k]));
  }
  return out;
}

struct Run {
  double ns = 0.0;
  int hits = 0;
  long points = 0;
  double sink = 0.0;
};

using Clock = std::chrono::steady_clock;

Run run_hedra(const Family& f, bool warm, bool box_path = true) {
  ContactSettings settings;
  settings.contact_distance = f.contact_distance;
  settings.box_box_path = box_path;
  ContactCache cache;
  Run r;
  const Shape a = f.a, b = f.b;
  const auto start = Clock::now();
  for (std::size_t k = 0; k < f.pose_a.size(); ++k) {
    const ContactResult c = contact(a, f.pose_a[k], b, f.pose_b[k], warm ? &cache : nullptr, settings);
    r.hits += c.stats.cache_hit;
    r.points += c.count;
    r.sink += c.distance;
  }
  r.ns = std::chrono::duration<double, std::nano>(Clock::now() - start).count() / f.pose_a.size();
  return r;
}

Run run_bullet(const BulletFamily& f) {
  Run r;
  const auto start = Clock::now();
  for (std::size_t k = 0; k < f.ta.size(); ++k) {
    btBoxBoxDetector detector(f.a.get(), f.b.get());  // as btBoxBoxCollisionAlgorithm::processCollision
    btDiscreteCollisionDetectorInterface::ClosestPointInput input;
    input.m_transformA = f.ta[k];
    input.m_transformB = f.tb[k];
    CountingResult result;
    detector.getClosestPoints(input, result, nullptr);
    r.points += result.points;
    r.sink += result.sum;
  }
  r.ns = std::chrono::duration<double, std::nano>(Clock::now() - start).count() / f.ta.size();
  return r;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// --verify N: N random box pairs (tumbling, resting face on face within
// 1e-3 rad, exactly touching, apart within the contact distance; every
// other pair rounded), the box path against the general polytope path
// (box_box_path = false): the same status, path, count, intersecting flag
// and points with their ids, distances and points to 1e-12 of the size.
// Prints the mismatches; exit 1 if any.
bool same_answer(const ContactResult& x, const ContactResult& y, double size) {
  const double tol = 1e-12 * size;
  if (x.status != y.status || x.path != y.path || x.count != y.count || x.intersecting != y.intersecting) return false;
  if (!(std::abs(x.distance - y.distance) <= tol) || !((x.normal - y.normal).norm() <= 1e-12)) return false;
  for (int k = 0; k < x.count; ++k) {
    bool found = false;
    for (int j = 0; j < y.count; ++j)
      found = found || ((x.points[k].point - y.points[j].point).norm() <= tol &&
                        std::abs(x.points[k].depth - y.points[j].depth) <= tol && x.points[k].id == y.points[j].id);
    if (!found) return false;
  }
  return true;
}

int verify(long pairs) {
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> u(-1.0, 1.0), h(0.05, 1.0), tilt(-1e-3, 1e-3);
  std::normal_distribution<double> g(0.0, 1.0);
  const auto random_rotation = [&] {
    return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
  };
  long mismatches = 0, with_points = 0, face_of_b = 0;
  for (long k = 0; k < pairs; ++k) {
    const int family = static_cast<int>(k % 4);
    const double margin = (k / 4) % 2 ? 0.05 * h(rng) : 0.0;
    const Box a{Vec(h(rng), h(rng), h(rng)), margin}, b{Vec(h(rng), h(rng), h(rng)), margin};
    Pose pa{random_rotation(), Vec(u(rng), u(rng), u(rng))}, pb;
    ContactSettings s;
    if (family == 0) {  // tumbling
      pb = {random_rotation(), pa.translation + 1.2 * Vec(u(rng), u(rng), u(rng))};
    } else {  // B on A's top face, tilted, yawed
      const Eigen::Matrix3d r =
          (Eigen::AngleAxisd(3.2 * u(rng), Vec::UnitZ()) * Eigen::AngleAxisd(tilt(rng), Vec::UnitX()) *
           Eigen::AngleAxisd(tilt(rng), Vec::UnitY()))
              .toRotationMatrix();
      const double gap = family == 1 ? -1e-2 * (0.01 + 0.99 * 0.5 * (1 + u(rng))) : (family == 2 ? 0.0 : 1e-3);
      const Vec local(0.5 * a.half_extents.x() * u(rng), 0.5 * a.half_extents.y() * u(rng),
                      a.half_extents.z() + b.half_extents.z() + 2 * margin + gap);
      pb = {pa.rotation * r, pa.apply(local)};
      if (family == 3) s.contact_distance = 2e-3;
    }
    const double size = a.half_extents.norm() + b.half_extents.norm() + 2 * margin;
    ContactSettings general = s;
    general.box_box_path = false;
    const ContactResult fast = contact(a, pa, b, pb, nullptr, s), slow = contact(a, pa, b, pb, nullptr, general);
    with_points += fast.count > 0;
    face_of_b += fast.path == ContactPath::face_b;
    if (!same_answer(fast, slow, size)) {
      if (++mismatches <= 10)
        std::printf("mismatch: pair %ld family %d margin %g: path %d/%d count %d/%d distance %.17g/%.17g\n", k, family,
                    margin, static_cast<int>(fast.path), static_cast<int>(slow.path), fast.count, slow.count,
                    fast.distance, slow.distance);
    }
  }
  std::printf(
      "%ld pairs (%ld with points, %ld on a face of B), %ld mismatches between the box path and the general path\n",
      pairs, with_points, face_of_b, mismatches);
  return mismatches == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 9;
  std::string filter, once, mode;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repeats" && i + 1 < argc) {
      repeats = std::max(1, std::atoi(argv[++i]));
    } else if (arg == "--filter" && i + 1 < argc) {
      filter = argv[++i];
    } else if (arg == "--verify" && i + 1 < argc) {
      return verify(std::atol(argv[++i]));
    } else if (arg == "--once" && i + 2 < argc) {
      once = argv[++i];
      mode = argv[++i];
    } else {
      std::fprintf(stderr,
                   "usage: box_contact_benchmark [--repeats N] [--filter SUBSTRING] [--once FAMILY "
                   "cold|warm|bullet|general-cold|general-warm|none] [--verify PAIRS]\n");
      return 2;
    }
  }
  const std::vector<Family> families = make_families();
  if (!once.empty()) {
    for (const Family& f : families) {
      if (f.name != once) continue;
      const BulletFamily bf = bullet_family(f);
      Run r;
      if (mode == "cold") r = run_hedra(f, false);
      if (mode == "warm") r = run_hedra(f, true);
      if (mode == "bullet") r = run_bullet(bf);
      if (mode == "general-cold") r = run_hedra(f, false, false);
      if (mode == "general-warm") r = run_hedra(f, true, false);
      std::printf("%s %s points %ld hits %d sink %.6g\n", f.name.c_str(), mode.c_str(), r.points, r.hits, r.sink);
      return 0;
    }
    std::fprintf(stderr, "no family %s\n", once.c_str());
    return 2;
  }
  std::printf("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", "family", "general cold ns",
              "general warm ns", "cold ns", "warm ns", "btBoxBoxDetector ns", "cold / bullet", "warm / cold", "hits",
              "points", "bullet points");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Family& f : families) {
    if (!filter.empty() && f.name.find(filter) == std::string::npos) continue;
    const BulletFamily bf = bullet_family(f);
    std::vector<double> general_cold, general_warm, cold, warm, bullet, cold_bt, warm_cold;
    Run c, w, b;
    for (int r = 0; r < repeats; ++r) {
      general_cold.push_back(run_hedra(f, false, false).ns);
      general_warm.push_back(run_hedra(f, true, false).ns);
      c = run_hedra(f, false);
      w = run_hedra(f, true);
      b = run_bullet(bf);
      cold.push_back(c.ns);
      warm.push_back(w.ns);
      bullet.push_back(b.ns);
      cold_bt.push_back(c.ns / b.ns);
      warm_cold.push_back(w.ns / c.ns);
    }
    std::printf("| %s | %.0f | %.0f | %.0f | %.0f | %.0f | %.2f | %.2f | %.1f %% | %.2f | %.2f |\n", f.name.c_str(),
                median(general_cold), median(general_warm), median(cold), median(warm), median(bullet), median(cold_bt),
                median(warm_cold), 100.0 * w.hits / f.pose_a.size(), static_cast<double>(c.points) / f.pose_a.size(),
                static_cast<double>(b.points) / f.pose_a.size());
  }
  return 0;
}
