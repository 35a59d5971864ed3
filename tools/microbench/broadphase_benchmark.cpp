// All overlapping pairs of N bodies: hedra's World beside Bullet's
// btCollisionWorld (btDbvtBroadphase, btCollisionDispatcher and
// btCollisionDispatcherMt) and FCL's DynamicAABBTreeCollisionManager, on
// the same scene, with brute force as the oracle up to 1e4 bodies.
//
// The scene: N bodies at a fixed density (kDensity bodies per unit volume)
// in a cube: random boxes, hulls of 8 to 32 points, and long thin boxes,
// sizes log-uniform over [0.5, 2], random orientations. Each frame moves
// every body by a small random step (the same steps for every library).
// Frame 0 builds (hedra: add + tree build; Bullet: add objects (dbvt
// insertion) and creates pair algorithms; FCL: register + setup); frames
// 1..F are the steady state, whose median per-frame time is the headline.
// Times are wall-clock medians; "broadphase" is the candidate search alone
// (hedra: PairSettings::broadphase_only; Bullet: updateAabbs +
// computeOverlappingPairs; FCL: collide with a callback that only counts).
// Memory: the heap growth over building the scene and running frame 0
// (glibc mallinfo2), the library's own structures and caches.
//
// Pairs: hedra answers penetration() (or contact()) for every pair whose
// distance is <= 0 (World's keep rule); Bullet reports manifolds, counted
// when a point's distance is <= 1e-9 (double-precision Bullet, margins 0);
// FCL counts collide()'s isCollision(). Each is compared with the oracle
// (penetration() on every pair whose bounding spheres overlap).
//
// Usage: broadphase_benchmark [--n 1000,10000,100000] [--frames 5]
//          [--query penetration|contact] [--threads 1,2] [--no-peers] [--no-oracle]
//        broadphase_benchmark --tree-study N   (refit against rebuild, 60 frames of drift)
#include <malloc.h>
#include <time.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <hedra/collision/world.hpp>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>

#ifdef HEDRA_WITH_PEERS
#  include <BulletCollision/CollisionDispatch/btCollisionDispatcherMt.h>
#  include <LinearMath/btThreads.h>
#  include <btBulletCollisionCommon.h>
#  include <fcl/fcl.h>
#endif

namespace {

using namespace hedra::collision;
using Vec = Eigen::Vector3d;
using Clock = std::chrono::steady_clock;
using PairSet = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

constexpr double kDensity = 0.12;  // bodies per unit volume

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }
// CPU time of the whole process (all threads): robust to other processes' load.
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}
std::size_t heap_bytes() { return mallinfo2().uordblks; }

struct Body {
  Shape shape;
  int kind = 0;  // 0 box, 1 hull, 2 long thin box
};

struct Scene {
  std::vector<Body> bodies;
  std::vector<std::vector<Pose>> frames;  // frames[f][i]
};

Scene make_scene(std::size_t n, int frames, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  Scene scene;
  const double side = std::cbrt(static_cast<double>(n) / kDensity);
  std::vector<Pose> poses;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = 0.5 * std::pow(4.0, u01(rng));
    Body b;
    b.kind = i % 10 < 4 ? 0 : (i % 10 < 8 ? 1 : 2);
    if (b.kind == 0) {
      b.shape = Box{s * Vec(0.2 + 0.4 * u01(rng), 0.2 + 0.4 * u01(rng), 0.2 + 0.4 * u01(rng)), 0.0};
    } else if (b.kind == 2) {
      b.shape = Box{s * Vec(1.5, 0.06, 0.06), 0.0};
    } else {
      const int count = 8 + static_cast<int>(rng() % 25);
      const Vec radii = s * Vec(0.3 + 0.4 * u01(rng), 0.3 + 0.4 * u01(rng), 0.3 + 0.4 * u01(rng));
      std::vector<Vec> points;
      for (int k = 0; k < count; ++k) points.push_back(Vec(g(rng), g(rng), g(rng)).normalized().cwiseProduct(radii));
      b.shape = Polyhedron{ConvexPolyhedron::build(points).polyhedron, 0.0};
    }
    scene.bodies.push_back(b);
    poses.push_back(Pose::from_quaternion(Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)),
                                          0.5 * side * Vec(u(rng), u(rng), u(rng))));
  }
  scene.frames.push_back(poses);
  for (int f = 1; f <= frames; ++f) {
    for (Pose& p : poses) {
      const Eigen::Quaterniond q(Eigen::AngleAxisd(0.01 * g(rng), Vec(g(rng), g(rng), g(rng)).normalized()));
      p.rotation = q.toRotationMatrix() * p.rotation;
      p.translation += 0.01 * Vec(u(rng), u(rng), u(rng));
    }
    scene.frames.push_back(poses);
  }
  return scene;
}

// The oracle: penetration() on every pair whose bounding spheres overlap
// (a pair farther apart cannot touch), kept by World's rule (distance <= band).
PairSet brute_force(const Scene& scene, const std::vector<Pose>& poses) {
  const std::size_t n = scene.bodies.size();
  std::vector<Vec> centre(n);
  std::vector<double> radius(n);
  for (std::size_t i = 0; i < n; ++i) {
    radius[i] = bounding_radius(scene.bodies[i].shape);
    Vec offset = Vec::Zero();
    if (const auto* p = std::get_if<Polyhedron>(&scene.bodies[i].shape)) offset = p->hull->offset();
    centre[i] = poses[i].apply(offset);
  }
  PairSet out;
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t j = i + 1; j < n; ++j) {
      const double reach = radius[i] + radius[j];
      if ((centre[i] - centre[j]).squaredNorm() > reach * reach * (1.0 + 1e-9)) continue;
      const PenetrationResult r = penetration(scene.bodies[i].shape, poses[i], scene.bodies[j].shape, poses[j]);
      if (r.status != Status::ok || r.distance <= World::kTouchingBand * std::max(radius[i], radius[j]))
        out.emplace_back(i, j);
    }
  return out;
}

struct Measure {
  std::string library;
  int threads = 1;
  double build = 0.0, frame0 = 0.0, frame = 0.0, broadphase = 0.0;
  double frame_cpu = 0.0;  // CPU seconds of all threads in a steady frame (median)
  double broadphase_cpu = 0.0;
  std::size_t candidates = 0, pairs = 0;
  long missing = -1, extra = -1;  // against the oracle (-1: no oracle)
  double memory_mb = 0.0;
  std::string note;
};

void compare_with(Measure& m, PairSet found, const PairSet* oracle) {
  std::sort(found.begin(), found.end());
  m.pairs = found.size();
  if (!oracle) return;
  PairSet miss, extra;
  std::set_difference(oracle->begin(), oracle->end(), found.begin(), found.end(), std::back_inserter(miss));
  std::set_difference(found.begin(), found.end(), oracle->begin(), oracle->end(), std::back_inserter(extra));
  m.missing = static_cast<long>(miss.size());
  m.extra = static_cast<long>(extra.size());
}

Measure run_hedra(const Scene& scene, PairQuery query, int threads, const PairSet* oracle) {
  Measure m;
  m.library = std::string("hedra World (") + (query == PairQuery::contact ? "contact" : "penetration") + ")";
  m.threads = threads;
  const std::size_t heap0 = heap_bytes();
  Clock::time_point start = Clock::now();
  World world;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) world.add(scene.bodies[i].shape, scene.frames[0][i]);
  PairSettings settings;
  settings.query = query;
  settings.parallel.threads = threads;
  std::vector<PairResult> out;
  world.pairs(settings, out);
  m.frame0 = seconds_since(start);
  m.build = m.frame0 - world.stats().query_seconds;
  m.memory_mb = static_cast<double>(heap_bytes() - heap0) / 1e6;
  PairSet found;
  for (const PairResult& r : out) found.emplace_back(r.a, r.b);
  std::vector<double> frames, broad, cpu, broad_cpu, update, traverse, serial;
  std::vector<PairResult> candidates;
  for (std::size_t f = 1; f < scene.frames.size(); ++f) {
    world.set_poses(scene.frames[f].data(), scene.frames[f].size());
    const double cpu0 = cpu_seconds();
    start = Clock::now();
    world.pairs(settings, out);
    frames.push_back(seconds_since(start));
    cpu.push_back(cpu_seconds() - cpu0);
    update.push_back(world.stats().update_seconds);
    serial.push_back(world.stats().serial_seconds / frames.back());
    traverse.push_back(world.stats().broadphase_seconds);
    PairSettings only = settings;
    only.broadphase_only = true;
    const double cpu1 = cpu_seconds();
    start = Clock::now();
    world.pairs(only, candidates);
    broad.push_back(seconds_since(start));
    broad_cpu.push_back(cpu_seconds() - cpu1);
    m.candidates = candidates.size();
  }
  m.frame = median(frames);
  m.frame_cpu = median(cpu);
  m.broadphase = median(broad);
  m.broadphase_cpu = median(broad_cpu);
  if (scene.frames.size() > 1) {
    found.clear();
    for (const PairResult& r : out) found.emplace_back(r.a, r.b);
  }
  compare_with(m, found, oracle);
  char note[160];
  std::snprintf(note, sizeof note, "frame: boxes+refit %.2f ms, traversal+sort %.2f ms, serial %.1f %%; rebuilt: %s",
                1e3 * median(update), 1e3 * median(traverse), 100.0 * median(serial),
                world.stats().rebuilt ? "yes" : "no");
  m.note = note;
  return m;
}

// When a rebuild pays: the same drifting scene (every body moves `step`
// per frame in a random direction kept for the run) queried with the tree
// refitted, rebuilt, and by the automatic rule; per frame the refitted
// tree's cost ratio and each mode's CPU time.
void tree_update_study(std::size_t n, int frames, double step) {
  Scene scene = make_scene(n, 0, 7 + n);
  std::mt19937_64 rng(9);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Vec> velocity;
  for (std::size_t i = 0; i < n; ++i) velocity.push_back(step * Vec(g(rng), g(rng), g(rng)).normalized());
  World worlds[3];
  const TreeUpdate modes[3] = {TreeUpdate::refit, TreeUpdate::rebuild, TreeUpdate::automatic};
  std::vector<Pose> poses = scene.frames[0];
  for (World& w : worlds)
    for (std::size_t i = 0; i < n; ++i) w.add(scene.bodies[i].shape, poses[i]);
  std::printf(
      "| frame | moved (body sizes) | refit cost ratio | refit ms | rebuild ms | automatic ms | automatic rebuilt |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  std::vector<PairResult> out;
  for (int f = 0; f <= frames; ++f) {
    double ms[3];
    for (int k = 0; k < 3; ++k) {
      worlds[k].set_poses(poses.data(), n);
      PairSettings s;
      s.parallel.threads = 1;
      s.tree_update = modes[k];
      const double cpu0 = cpu_seconds();
      worlds[k].pairs(s, out);
      ms[k] = 1e3 * (cpu_seconds() - cpu0);
    }
    if (f % 5 == 0)
      std::printf("| %d | %.2f | %.3f | %.2f | %.2f | %.2f | %s |\n", f, f * step, worlds[0].stats().tree_cost_ratio,
                  ms[0], ms[1], ms[2], worlds[2].stats().rebuilt ? "yes" : "no");
    for (std::size_t i = 0; i < n; ++i) poses[i].translation += velocity[i];
  }
}

#ifdef HEDRA_WITH_PEERS

btTransform bullet_transform(const Pose& p) {
  const Eigen::Matrix3d& r = p.rotation;
  btMatrix3x3 basis(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2));
  return btTransform(basis, btVector3(p.translation.x(), p.translation.y(), p.translation.z()));
}

std::unique_ptr<btCollisionShape> bullet_shape(const Shape& shape) {
  if (const auto* b = std::get_if<Box>(&shape)) {
    auto box = std::make_unique<btBoxShape>(btVector3(b->half_extents.x(), b->half_extents.y(), b->half_extents.z()));
    box->setMargin(0.0);  // btBoxShape keeps its outer size
    return box;
  }
  const ConvexPolyhedron& hull = *std::get<Polyhedron>(shape).hull;
  auto convex = std::make_unique<btConvexHullShape>();
  for (const Vec& v : hull.vertices()) {
    const Vec x = v + hull.offset();
    convex->addPoint(btVector3(x.x(), x.y(), x.z()), false);
  }
  convex->recalcLocalAabb();
  convex->setMargin(0.0);
  return convex;
}

Measure run_bullet(const Scene& scene, bool multithreaded, int threads, const PairSet* oracle) {
  Measure m;
  m.library = multithreaded ? "Bullet btCollisionDispatcherMt" : "Bullet btCollisionDispatcher";
  m.threads = threads;
  if (multithreaded) {
    btITaskScheduler* scheduler = btGetTaskScheduler();
    if (!scheduler || std::string(scheduler->getName()) == "Sequential") {
      static btITaskScheduler* created = btCreateDefaultTaskScheduler();
      if (!created) {
        m.note = "Debian's Bullet has no thread-safe task scheduler (BT_THREADSAFE off)";
        return m;
      }
      btSetTaskScheduler(created);
    }
    btGetTaskScheduler()->setNumThreads(threads);
    m.note = std::string("scheduler ") + btGetTaskScheduler()->getName();
  }
  const std::size_t heap0 = heap_bytes();
  Clock::time_point start = Clock::now();
  btDefaultCollisionConfiguration config;
  std::unique_ptr<btCollisionDispatcher> dispatcher = multithreaded
                                                          ? std::make_unique<btCollisionDispatcherMt>(&config, 40)
                                                          : std::make_unique<btCollisionDispatcher>(&config);
  btDbvtBroadphase broadphase;
  btCollisionWorld world(dispatcher.get(), &broadphase, &config);
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btCollisionObject>> objects;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    shapes.push_back(bullet_shape(scene.bodies[i].shape));
    objects.push_back(std::make_unique<btCollisionObject>());
    objects.back()->setCollisionShape(shapes.back().get());
    objects.back()->setWorldTransform(bullet_transform(scene.frames[0][i]));
    objects.back()->setUserIndex(static_cast<int>(i));
    world.addCollisionObject(objects.back().get());
  }
  m.build = seconds_since(start);
  world.performDiscreteCollisionDetection();
  m.frame0 = seconds_since(start);
  m.memory_mb = static_cast<double>(heap_bytes() - heap0) / 1e6;
  std::vector<double> frames, broad, cpu, broad_cpu;
  for (std::size_t f = 1; f < scene.frames.size(); ++f) {
    for (std::size_t i = 0; i < objects.size(); ++i)
      objects[i]->setWorldTransform(bullet_transform(scene.frames[f][i]));
    const double cpu0 = cpu_seconds();
    start = Clock::now();
    world.updateAabbs();
    world.computeOverlappingPairs();
    broad.push_back(seconds_since(start));
    broad_cpu.push_back(cpu_seconds() - cpu0);
    dispatcher->dispatchAllCollisionPairs(broadphase.getOverlappingPairCache(), world.getDispatchInfo(),
                                          dispatcher.get());
    frames.push_back(seconds_since(start));
    cpu.push_back(cpu_seconds() - cpu0);
  }
  m.frame = median(frames);
  m.frame_cpu = median(cpu);
  m.broadphase = median(broad);
  m.broadphase_cpu = median(broad_cpu);
  m.candidates = static_cast<std::size_t>(broadphase.getOverlappingPairCache()->getNumOverlappingPairs());
  PairSet found;
  for (int k = 0; k < dispatcher->getNumManifolds(); ++k) {
    const btPersistentManifold* manifold = dispatcher->getManifoldByIndexInternal(k);
    bool touching = false;
    for (int p = 0; p < manifold->getNumContacts(); ++p) touching |= manifold->getContactPoint(p).getDistance() <= 1e-9;
    if (!touching) continue;
    auto a = static_cast<std::uint32_t>(manifold->getBody0()->getUserIndex());
    auto b = static_cast<std::uint32_t>(manifold->getBody1()->getUserIndex());
    found.emplace_back(std::min(a, b), std::max(a, b));
  }
  compare_with(m, found, oracle);
  for (auto& object : objects) world.removeCollisionObject(object.get());
  return m;
}

std::shared_ptr<fcl::CollisionGeometryd> fcl_shape(const Shape& shape) {
  if (const auto* b = std::get_if<Box>(&shape)) return std::make_shared<fcl::Boxd>(2.0 * b->half_extents);
  const ConvexPolyhedron& hull = *std::get<Polyhedron>(shape).hull;
  auto vertices = std::make_shared<std::vector<Vec>>();
  for (const Vec& v : hull.vertices()) vertices->push_back(v + hull.offset());
  auto faces = std::make_shared<std::vector<int>>();
  const auto polygons = hull.mesh().polygons();
  for (const auto& polygon : polygons) {
    faces->push_back(static_cast<int>(polygon.size()));
    for (auto v : polygon) faces->push_back(static_cast<int>(v));
  }
  return std::make_shared<fcl::Convexd>(vertices, static_cast<int>(polygons.size()), faces);
}

fcl::Transform3d fcl_transform(const Pose& p) {
  fcl::Transform3d t = fcl::Transform3d::Identity();
  t.linear() = p.rotation;
  t.translation() = p.translation;
  return t;
}

struct FclData {
  fcl::CollisionRequestd request;
  PairSet found;
  std::size_t candidates = 0;
  bool broadphase_only = false;
};

bool fcl_callback(fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* data) {
  auto& d = *static_cast<FclData*>(data);
  ++d.candidates;
  if (d.broadphase_only) return false;
  fcl::CollisionResultd result;
  fcl::collide(o1, o2, d.request, result);
  if (result.isCollision()) {
    const auto a = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(o1->getUserData()));
    const auto b = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(o2->getUserData()));
    d.found.emplace_back(std::min(a, b), std::max(a, b));
  }
  return false;
}

Measure run_fcl(const Scene& scene, const PairSet* oracle) {
  Measure m;
  m.library = "FCL DynamicAABBTree (contact)";
  const std::size_t heap0 = heap_bytes();
  Clock::time_point start = Clock::now();
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;
  std::vector<fcl::CollisionObjectd*> pointers;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    objects.push_back(
        std::make_unique<fcl::CollisionObjectd>(fcl_shape(scene.bodies[i].shape), fcl_transform(scene.frames[0][i])));
    objects.back()->setUserData(reinterpret_cast<void*>(static_cast<std::uintptr_t>(i)));
    pointers.push_back(objects.back().get());
  }
  fcl::DynamicAABBTreeCollisionManagerd manager;
  manager.registerObjects(pointers);
  manager.setup();
  m.build = seconds_since(start);
  FclData data;
  data.request.enable_contact = true;  // penetration depth and a contact point
  data.request.num_max_contacts = 1;
  manager.collide(&data, fcl_callback);
  m.frame0 = seconds_since(start);
  m.memory_mb = static_cast<double>(heap_bytes() - heap0) / 1e6;
  std::vector<double> frames, broad, cpu, broad_cpu;
  for (std::size_t f = 1; f < scene.frames.size(); ++f) {
    const double cpu0 = cpu_seconds();
    start = Clock::now();
    for (std::size_t i = 0; i < objects.size(); ++i) {
      objects[i]->setTransform(fcl_transform(scene.frames[f][i]));
      objects[i]->computeAABB();
    }
    manager.update();
    data.found.clear();
    data.candidates = 0;
    manager.collide(&data, fcl_callback);
    frames.push_back(seconds_since(start));
    cpu.push_back(cpu_seconds() - cpu0);
    FclData only;
    only.broadphase_only = true;
    const double cpu1 = cpu_seconds();
    start = Clock::now();
    manager.collide(&only, fcl_callback);
    broad.push_back(seconds_since(start));
    broad_cpu.push_back(cpu_seconds() - cpu1);
    m.candidates = only.candidates;
  }
  m.frame = median(frames);
  m.frame_cpu = median(cpu);
  m.broadphase = median(broad);
  m.broadphase_cpu = median(broad_cpu);
  compare_with(m, data.found, oracle);
  return m;
}

#endif

std::vector<std::size_t> parse_list(const char* text) {
  std::vector<std::size_t> out;
  for (const char* p = text; *p;) {
    out.push_back(static_cast<std::size_t>(std::atof(p)));
    while (*p && *p != ',') ++p;
    if (*p == ',') ++p;
  }
  return out;
}

void print(std::size_t n, const Measure& m) {
  char missing[64] = "-";
  if (m.missing >= 0) std::snprintf(missing, sizeof missing, "%ld/%ld", m.missing, m.extra);
  std::printf("| %6zu | %-32s | %d | %8.2f | %8.2f | %8.2f | %8.2f | %9.2f | %9.2f | %9zu | %7zu | %9s | %7.1f | %s\n",
              n, m.library.c_str(), m.threads, 1e3 * m.build, 1e3 * m.frame0, 1e3 * m.broadphase,
              1e3 * m.broadphase_cpu, 1e3 * m.frame, 1e3 * m.frame_cpu, m.candidates, m.pairs, missing, m.memory_mb,
              m.note.c_str());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> sizes = {1000, 10000, 100000};
  std::vector<std::size_t> thread_counts = {1, 2};
  int frames = 5;
  bool peers = true;
  std::size_t oracle_limit = 10000;
  PairQuery query = PairQuery::penetration;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--n" && i + 1 < argc)
      sizes = parse_list(argv[++i]);
    else if (arg == "--threads" && i + 1 < argc)
      thread_counts = parse_list(argv[++i]);
    else if (arg == "--frames" && i + 1 < argc)
      frames = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--query" && i + 1 < argc)
      query = std::string(argv[++i]) == "contact" ? PairQuery::contact : PairQuery::penetration;
    else if (arg == "--no-peers")
      peers = false;
    else if (arg == "--no-oracle")
      oracle_limit = 0;
    else if (arg == "--tree-study" && i + 1 < argc) {
      tree_update_study(static_cast<std::size_t>(std::atof(argv[++i])), 60, 0.1);
      return 0;
    } else {
      std::fprintf(stderr,
                   "usage: %s [--n 1000,10000] [--threads 1,2] [--frames 5] [--query penetration|contact] [--no-peers] "
                   "[--no-oracle]\n",
                   argv[0]);
      return 2;
    }
  }
  std::printf(
      "| N | library | threads | build ms | frame 0 ms | broadphase ms | broadphase CPU ms | frame ms | frame CPU ms | "
      "candidates | pairs | missed/extra | memory MB | note\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (std::size_t n : sizes) {
    const Scene scene = make_scene(n, frames, 42 + n);
    PairSet oracle;
    const bool with_oracle = n <= oracle_limit;
    if (with_oracle) oracle = brute_force(scene, scene.frames.back());
    const PairSet* o = with_oracle ? &oracle : nullptr;
    for (std::size_t t : thread_counts) print(n, run_hedra(scene, query, static_cast<int>(t), o));
#ifdef HEDRA_WITH_PEERS
    if (peers) {
      print(n, run_bullet(scene, false, 1, o));
      for (std::size_t t : thread_counts) print(n, run_bullet(scene, true, static_cast<int>(t), o));
      print(n, run_fcl(scene, o));
    }
#endif
  }
  return 0;
}
