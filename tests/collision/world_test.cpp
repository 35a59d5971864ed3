// World (world.hpp): the all-pairs query against brute force (every pair
// through the same single query and the documented keep rule) on random
// scenes, touching pairs, long thin boxes, sizes from 1e-4 to 1e4 and
// scenes far from the origin, for every query type and several
// max_distance; identical bits for 1, 2 and all threads and any runner;
// moving bodies (refit and rebuild agree with brute force); the filter and
// ignored pairs; tight boxes (containment and tightness against supports);
// bad input. Fixed seeds.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstring>
#include <hedra/collision/detail/support.hpp>
#include <hedra/collision/world.hpp>
#include <random>
#include <thread>
#include <vector>

#include "allocation_counter.hpp"

namespace hedra::collision {
namespace {

using Vec = Eigen::Vector3d;

bool same_bits(double x, double y) { return std::memcmp(&x, &y, sizeof(double)) == 0; }
bool same_bits(const Vec& x, const Vec& y) { return std::memcmp(x.data(), y.data(), 3 * sizeof(double)) == 0; }

bool same(const PairResult& x, const PairResult& y) {
  if (!(x.a == y.a && x.b == y.b && x.status == y.status && x.intersecting == y.intersecting &&
        same_bits(x.distance, y.distance) && same_bits(x.normal, y.normal) && same_bits(x.point_a, y.point_a) &&
        same_bits(x.point_b, y.point_b) && same_bits(x.error_bound, y.error_bound) && x.count == y.count))
    return false;
  for (int k = 0; k < x.count; ++k)
    if (!same_bits(x.points[k].point, y.points[k].point) || !same_bits(x.points[k].depth, y.points[k].depth) ||
        x.points[k].id != y.points[k].id)
      return false;
  return true;
}

// The documented keep rule, applied to the single query on every pair.
bool brute_keep(const World& w, std::uint32_t i, std::uint32_t j, const PairSettings& s) {
  const Shape &a = w.shape(i), &b = w.shape(j);
  const Pose &pa = w.pose(i), &pb = w.pose(j);
  const double reach = s.max_distance + World::kTouchingBand * std::max(bounding_radius(a), bounding_radius(b));
  switch (s.query) {
    case PairQuery::intersect:
      if (s.max_distance == 0.0) {
        const IntersectResult r = intersect(a, pa, b, pb, nullptr, s.gjk);
        return r.status != Status::ok || r.intersecting;
      } else {
        const DistanceResult r = distance(a, pa, b, pb, nullptr, s.gjk);
        return r.status != Status::ok || r.distance <= reach;
      }
    case PairQuery::distance: {
      const DistanceResult r = distance(a, pa, b, pb, nullptr, s.gjk);
      return r.status != Status::ok || r.distance <= reach;
    }
    case PairQuery::penetration: {
      const PenetrationResult r = penetration(a, pa, b, pb, nullptr, s.penetration);
      return r.status != Status::ok || r.distance <= reach;
    }
    case PairQuery::contact: {
      ContactSettings cs = s.contact;
      cs.contact_distance = s.max_distance;
      const ContactResult r = contact(a, pa, b, pb, nullptr, cs);
      return r.status != Status::ok || (r.path != ContactPath::separated && r.distance <= reach);
    }
  }
  return false;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> brute_pairs(const World& w, const PairSettings& s,
                                                                 const std::vector<std::uint32_t>& group,
                                                                 const std::vector<std::uint32_t>& mask) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  const auto n = static_cast<std::uint32_t>(w.size());
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t j = i + 1; j < n; ++j)
      if ((group[i] & mask[j]) && (group[j] & mask[i]) && brute_keep(w, i, j, s)) out.emplace_back(i, j);
  return out;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> ids(const std::vector<PairResult>& r) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  for (const PairResult& p : r) out.emplace_back(p.a, p.b);
  return out;
}

class ReverseSerialRunner final : public TaskRunner {
 public:
  int concurrency() const override { return 4; }
  void run(std::size_t n, void (*task)(std::size_t, void*), void* context) override {
    for (std::size_t i = n; i-- > 0;) task(i, context);
  }
};

struct Scene {
  std::vector<Shape> shapes;
  std::vector<Pose> poses;
  std::vector<std::uint32_t> group, mask;
};

Eigen::Quaterniond random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng));
}

std::shared_ptr<const ConvexPolyhedron> random_hull(std::mt19937_64& rng, int n, const Vec& scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Vec> points;
  for (int i = 0; i < n; ++i) points.push_back(Vec(u(rng), u(rng), u(rng)).cwiseProduct(scale));
  return ConvexPolyhedron::build(points).polyhedron;
}

// n random bodies of every kind, sizes size * [0.5, 1.5] (times `spread`^u
// for u in [-1, 1] when spread > 1), in a cube of side `extent` at `centre`.
Scene random_scene(std::uint64_t seed, int n, double size, double spread, double extent, const Vec& centre) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  Scene scene;
  for (int i = 0; i < n; ++i) {
    const double s = size * (1.0 + 0.5 * u(rng)) * std::pow(spread, u(rng));
    Shape shape;
    switch (i % 7) {
      case 0:
        shape = Box{s * Vec(0.5 + u01(rng), 0.5 + u01(rng), 0.5 + u01(rng)), 0.0};
        break;
      case 1:
        shape = Box{s * Vec(4.0, 0.05, 0.05), 0.0};
        break;  // long and thin
      case 2:
        shape = Polyhedron{random_hull(rng, 8 + i % 25, s * Vec(1.0, 0.7, 0.5)), i % 3 == 0 ? 0.1 * s : 0.0};
        break;
      case 3:
        shape = Sphere{0.6 * s, 0.0};
        break;
      case 4:
        shape = Capsule{0.3 * s, 0.8 * s, 0.0};
        break;
      case 5:
        shape = Cylinder{0.5 * s, 0.6 * s, i % 2 ? 0.05 * s : 0.0};
        break;
      default:
        shape = Cone{0.5 * s, 0.7 * s, 0.0};
        break;
    }
    scene.shapes.push_back(shape);
    scene.poses.push_back(
        Pose::from_quaternion(random_rotation(rng), centre + 0.5 * extent * Vec(u(rng), u(rng), u(rng))));
    scene.group.push_back(1u << (i % 3));
    scene.mask.push_back(i % 5 == 0 ? ~(1u << ((i + 1) % 3)) : 0xFFFFFFFFu);
  }
  return scene;
}

World make_world(const Scene& scene) {
  World world;
  for (std::size_t i = 0; i < scene.shapes.size(); ++i)
    EXPECT_EQ(world.add(scene.shapes[i], scene.poses[i], scene.group[i], scene.mask[i]), i);
  return world;
}

// pairs() equals brute force for every query and distance, and the same bits
// for every thread count and runner.
void check_scene(const Scene& scene, const std::vector<double>& distances, const char* what, int* found = nullptr) {
  static ReverseSerialRunner reverse;
  World world = make_world(scene);
  for (PairQuery q : {PairQuery::intersect, PairQuery::distance, PairQuery::penetration, PairQuery::contact}) {
    for (double d : distances) {
      PairSettings s;
      s.query = q;
      s.max_distance = d;
      const auto expected = brute_pairs(world, s, scene.group, scene.mask);
      std::vector<PairResult> reference;
      s.parallel = {1, nullptr};
      world.pairs(s, reference);
      ASSERT_EQ(ids(reference), expected) << what << " query " << int(q) << " max_distance " << d;
      if (found) *found += static_cast<int>(expected.size());
      EXPECT_GE(world.stats().candidates, expected.size());
      for (const ParallelSettings& p :
           {ParallelSettings{2, nullptr}, ParallelSettings{0, nullptr}, ParallelSettings{0, &reverse}}) {
        s.parallel = p;
        std::vector<PairResult> out;
        world.pairs(s, out);
        ASSERT_EQ(out.size(), reference.size()) << what;
        for (std::size_t k = 0; k < out.size(); ++k)
          ASSERT_TRUE(same(out[k], reference[k])) << what << " pair " << k << " threads " << p.threads;
      }
    }
  }
}

TEST(World, AllPairsEqualBruteForceOnRandomScenes) {
  int found = 0;
  check_scene(random_scene(1, 300, 1.0, 1.0, 12.0, Vec::Zero()), {0.0, 0.01, 0.5}, "unit sizes", &found);
  EXPECT_GT(found, 300);  // the scene has pairs to find
}

TEST(World, AllPairsEqualBruteForceWithSizesFrom1em4To1e4) {
  check_scene(random_scene(2, 200, 1.0, 1e4, 60.0, Vec::Zero()), {0.0, 0.3}, "mixed sizes");
}

TEST(World, AllPairsEqualBruteForceFarFromTheOrigin) {
  check_scene(random_scene(3, 200, 1.0, 1.0, 10.0, Vec(1e6, -3e6, 2e5)), {0.0, 0.01}, "far");
  check_scene(random_scene(4, 120, 1e-3, 1.0, 1e-2, Vec(1e3, 1e3, -1e3)), {0.0, 1e-5}, "tiny and far");
}

// Bodies placed exactly touching (faces, edges, a sphere on a face, long thin
// boxes end to end): the distance is 0 up to rounding, and every such pair is
// found with max_distance 0.
TEST(World, TouchingPairsAreNeverMissed) {
  Scene scene;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto push = [&](const Shape& shape, const Pose& pose) {
    scene.shapes.push_back(shape);
    scene.poses.push_back(pose);
    scene.group.push_back(1);
    scene.mask.push_back(0xFFFFFFFFu);
  };
  for (int k = 0; k < 40; ++k) {
    const Vec base(30.0 * k, 7.0 * u(rng), 1e5);
    const double h = std::pow(10.0, 2.0 * u(rng));
    // Two boxes face to face along x, a third touching along a rotated edge.
    push(Box{Vec(h, 0.5 * h, 0.25 * h), 0.0}, Pose::from_translation(base));
    push(Box{Vec(h, 0.5 * h, 0.25 * h), 0.0}, Pose::from_translation(base + Vec(2.0 * h, 0.0, 0.0)));
    push(Sphere{0.3 * h, 0.0}, Pose::from_translation(base + Vec(0.0, 0.0, 0.55 * h)));
    push(Box{Vec(10.0 * h, 0.01 * h, 0.01 * h), 0.0}, Pose::from_translation(base + Vec(-11.0 * h, 0.0, 0.0)));
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7 + 0.1 * k, Vec(0, 0, 1)));
    push(Capsule{0.1 * h, h, 0.0}, Pose::from_quaternion(q, base + Vec(0.0, -0.6 * h, 0.0)));
  }
  int found = 0;
  check_scene(scene, {0.0}, "touching", &found);
  EXPECT_GE(found, 4 * 40 * 3);  // box-box, box-sphere, box-thin, box-capsule for every query type but intersect's
}

// Moving bodies: frames of random motion; refit, rebuild and automatic
// agree with brute force each frame.
TEST(World, MovingBodiesRefitOrRebuildAndStayExact) {
  Scene scene = random_scene(6, 250, 1.0, 1.0, 10.0, Vec::Zero());
  World refit = make_world(scene), rebuild = make_world(scene), automatic = make_world(scene);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  bool rebuilt_automatically = false;
  std::vector<PairResult> first;
  for (World* w : {&refit, &rebuild, &automatic}) {
    w->pairs({}, first);  // builds the trees
    EXPECT_TRUE(w->stats().rebuilt);
  }
  for (int frame = 0; frame < 12; ++frame) {
    const double step = frame < 6 ? 0.05 : 1.5;  // then large moves: the refitted tree degrades
    for (Pose& p : scene.poses) p.translation += step * Vec(u(rng), u(rng), u(rng));
    scene.poses[frame].translation.x() = std::numeric_limits<double>::infinity();  // rejected, nothing changes
    EXPECT_FALSE(refit.set_poses(scene.poses.data(), scene.poses.size()));
    scene.poses[frame].translation.x() = 0.0;
    ASSERT_TRUE(refit.set_poses(scene.poses.data(), scene.poses.size()));
    ASSERT_TRUE(rebuild.set_poses(scene.poses.data(), scene.poses.size()));
    for (std::uint32_t i = 0; i < scene.poses.size(); ++i) ASSERT_TRUE(automatic.set_pose(i, scene.poses[i]));
    PairSettings s;
    s.max_distance = 0.02;
    const auto expected = brute_pairs(refit, s, scene.group, scene.mask);
    std::vector<PairResult> a, b, c;
    s.tree_update = TreeUpdate::refit;
    refit.pairs(s, a);
    EXPECT_FALSE(refit.stats().rebuilt);
    s.tree_update = TreeUpdate::rebuild;
    rebuild.pairs(s, b);
    EXPECT_TRUE(rebuild.stats().rebuilt);
    s.tree_update = TreeUpdate::automatic;
    automatic.pairs(s, c);
    rebuilt_automatically |= automatic.stats().rebuilt;
    ASSERT_EQ(ids(a), expected) << frame;
    ASSERT_EQ(ids(b), expected) << frame;
    ASSERT_EQ(ids(c), expected) << frame;
  }
  EXPECT_TRUE(rebuilt_automatically);
  EXPECT_GT(refit.stats().tree_cost_ratio, World::kRebuildCostRatio);
}

// Once its arrays have grown, a frame (moved poses, refit, candidates,
// queries, the output) allocates nothing, on one thread and on the pool.
TEST(World, SteadyFramesAllocateNothing) {
  Scene scene = random_scene(13, 400, 1.0, 1.0, 12.0, Vec::Zero());
  World world = make_world(scene);
  std::vector<PairResult> out;
  for (PairQuery q : {PairQuery::penetration, PairQuery::contact}) {
    for (int threads : {1, 2, 0}) {
      PairSettings s;
      s.query = q;
      s.max_distance = 0.05;
      s.parallel.threads = threads;
      s.tree_update = TreeUpdate::refit;
      for (int frame = 0; frame < 3; ++frame) {  // warm-up: every chunk's arrays reach their size
        world.set_poses(scene.poses.data(), scene.poses.size());
        world.pairs(s, out);
      }
      const std::size_t found = out.size();
      for (Pose& p : scene.poses) p.translation.x() += 1e-7;
      world.set_poses(scene.poses.data(), scene.poses.size());
      const long before = g_allocations.load();
      world.pairs(s, out);
      EXPECT_EQ(g_allocations.load(), before) << "query " << int(q) << " threads " << threads;
      EXPECT_EQ(out.size(), found);
      EXPECT_GT(found, 50u);
    }
  }
}

TEST(World, FilterAndIgnoredPairs) {
  World world;
  const Box box{Vec(1, 1, 1), 0.0};
  for (int i = 0; i < 4; ++i)
    world.add(box, Pose::from_translation(Vec(0.5 * i, 0, 0)), i == 3 ? 2u : 1u, i == 3 ? 2u : 0xFFFFFFFFu);
  // 3 is in group 2 and sees only group 2: it pairs with nobody (0..2 are group 1).
  EXPECT_TRUE(world.ignore_pair(2, 0));
  EXPECT_TRUE(world.ignore_pair(0, 2));  // twice is once
  EXPECT_FALSE(world.ignore_pair(1, 1));
  EXPECT_FALSE(world.ignore_pair(1, 4));
  std::vector<PairResult> out;
  world.pairs({}, out);
  const std::vector<std::pair<std::uint32_t, std::uint32_t>> expected{{0, 1}, {1, 2}};
  EXPECT_EQ(ids(out), expected);
  for (const PairResult& r : out) EXPECT_TRUE(r.intersecting && r.distance < 0.0);
}

// separated_beyond: true only when GJK certifies a gap larger than asked.
TEST(World, SeparatedBeyondCertifiesTheGapItIsAsked) {
  const Sphere ball{1.0, 0.0};
  const Box box{Vec(1.0, 2.0, 3.0), 0.0};
  const Pose origin{};
  const Pose apart = Pose::from_translation(Vec(3.5, 0.0, 0.0));  // sphere-box gap 1.5, sphere-sphere 1.5
  EXPECT_TRUE(separated_beyond(ball, origin, ball, apart, 1.4));
  EXPECT_FALSE(separated_beyond(ball, origin, ball, apart, 1.6));
  EXPECT_TRUE(separated_beyond(box, origin, ball, Pose::from_translation(Vec(2.5, 0.0, 0.0)), 0.49));
  EXPECT_FALSE(separated_beyond(box, origin, ball, Pose::from_translation(Vec(2.5, 0.0, 0.0)), 0.51));
  EXPECT_FALSE(separated_beyond(box, origin, ball, Pose::from_translation(Vec(1.5, 0.0, 0.0)), 0.0));  // overlapping
  EXPECT_FALSE(separated_beyond(ball, origin, ball, apart, -1.0));
  EXPECT_FALSE(separated_beyond(Sphere{-1.0, 0.0}, origin, ball, apart, 0.0));
  EXPECT_FALSE(separated_beyond(ball, Pose::from_translation(Vec(NAN, 0, 0)), ball, apart, 0.0));
  // Agrees with the distance on random pairs, away from the threshold.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Scene scene = random_scene(12, 60, 1.0, 1.0, 6.0, Vec::Zero());
  int apart_count = 0;
  for (std::size_t i = 0; i + 1 < scene.shapes.size(); ++i) {
    const double d = distance(scene.shapes[i], scene.poses[i], scene.shapes[i + 1], scene.poses[i + 1]).distance;
    const double gap = std::abs(u(rng));
    if (std::abs(d - gap) < 1e-6) continue;
    const bool apart = separated_beyond(scene.shapes[i], scene.poses[i], scene.shapes[i + 1], scene.poses[i + 1], gap);
    EXPECT_EQ(apart, d > gap) << i << " distance " << d << " gap " << gap;
    apart_count += apart;
  }
  EXPECT_GT(apart_count, 10);
}

TEST(World, BadInputAddsNothingAndChangesNothing) {
  World world;
  EXPECT_EQ(world.add(Sphere{-1.0, 0.0}, Pose{}), World::kInvalidBody);
  EXPECT_EQ(world.add(Polyhedron{nullptr, 0.0}, Pose{}), World::kInvalidBody);
  EXPECT_EQ(world.add(Sphere{1.0, 0.0}, Pose::from_quaternion(Eigen::Quaterniond(0, 0, 0, 0), Vec::Zero())),
            World::kInvalidBody);
  EXPECT_EQ(world.size(), 0u);
  std::vector<PairResult> out(3);
  world.pairs({}, out);  // an empty world
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(world.add(Sphere{1.0, 0.0}, Pose{}), 0u);
  EXPECT_EQ(world.add(Sphere{1.0, 0.0}, Pose::from_translation(Vec(1.5, 0, 0))), 1u);
  EXPECT_FALSE(world.set_pose(2, Pose{}));
  EXPECT_FALSE(world.set_pose(0, Pose::from_translation(Vec(2e60, 0, 0))));
  EXPECT_FALSE(world.set_poses(nullptr, 2));
  const Pose one[1] = {Pose{}};
  EXPECT_FALSE(world.set_poses(one, 1));
  PairSettings s;
  world.pairs(s, out);
  EXPECT_EQ(out.size(), 1u);
  for (double d : {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    s.max_distance = d;
    world.pairs(s, out);
    EXPECT_TRUE(out.empty()) << d;
  }
}

// Boxes hold the shape (every support point in random directions) and are
// tight: each face is within the allowance of the shape's support value.
TEST(World, BoxesAreTightAndHoldTheShape) {
  const Scene scene = random_scene(8, 140, 1.0, 100.0, 50.0, Vec(-3e4, 0.0, 1e3));
  World world = make_world(scene);
  std::mt19937_64 rng(9);
  std::normal_distribution<double> g(0.0, 1.0);
  for (std::uint32_t i = 0; i < world.size(); ++i) {
    const World::Aabb box = world.box(i);
    const Pose& p = scene.poses[i];
    const double r = bounding_radius(scene.shapes[i]);
    const double allowance =
        World::kBoxBand * r + World::kBoxRounding * (p.translation.cwiseAbs().maxCoeff() + 2.0 * r);
    for (int k = 0; k < 3; ++k) {
      const Vec axis = Vec::Unit(k);
      const double hi = axis.dot(p.apply(support(scene.shapes[i], p.rotation.transpose() * axis)));
      const double lo = axis.dot(p.apply(support(scene.shapes[i], -(p.rotation.transpose() * axis))));
      EXPECT_GE(box.hi[k], hi) << i;
      EXPECT_LE(box.lo[k], lo) << i;
      // Tight: beyond the support value by the allowance (and the rounding of curved supports) only.
      EXPECT_LE(box.hi[k] - hi, 2.0 * allowance + 1e-12 * r) << i << " axis " << k;
      EXPECT_LE(lo - box.lo[k], 2.0 * allowance + 1e-12 * r) << i << " axis " << k;
    }
    for (int t = 0; t < 50; ++t) {
      const Vec d(g(rng), g(rng), g(rng));
      const Vec x = p.apply(support(scene.shapes[i], p.rotation.transpose() * d));
      EXPECT_TRUE((x.array() >= box.lo.array()).all() && (x.array() <= box.hi.array()).all()) << i;
    }
  }
}

}  // namespace
}  // namespace hedra::collision
