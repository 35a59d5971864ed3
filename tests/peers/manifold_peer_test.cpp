// Contact manifolds against Bullet 3.24's polyhedral path
// (btPolyhedralContactClipping::findSeparatingAxis + clipHullAgainstHull,
// double precision) on box and hull pairs. Where the deepest depths of hedra
// and Bullet disagree, the exact reference (qhull, signed) decides: hedra's
// deepest depth must stay within its contract (at most the exact depth plus
// the face bias); Bullet's misses are counted and printed. Fixed seeds.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <hedra/collision/manifold.hpp>
#include <random>

#include "../collision/collision_test_support.hpp"
#include "bullet_manifold.hpp"

namespace {

using hedra::collision::Box;
using hedra::collision::ContactResult;
using hedra::collision::ContactSettings;
using hedra::collision::Polyhedron;
using hedra::collision::Pose;
using hedra::collision::Shape;
using hedra::peers::PeerManifold;
using hedra::peers::PeerPair;
using Vec = Eigen::Vector3d;
namespace t = hedra::collision::testing;

double deepest(const ContactResult& r) {
  double d = -INFINITY;
  for (int k = 0; k < r.count; ++k) d = std::max(d, r.points[k].depth);
  return d;
}
double deepest(const PeerManifold& m) {
  double d = -INFINITY;
  for (const auto& p : m.points) d = std::max(d, p.depth);
  return d;
}

TEST(ManifoldPeer, BoxOnBoxAgreesWithBullet) {
  const PeerPair pair{Box{{1, 1, 1}}, Pose::identity(), Box{{0.5, 0.5, 0.5}},
                      Pose::from_quaternion(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Vec::UnitZ())), {0.1, 0, 1.45})};
  const auto bullet = hedra::peers::prepare_bullet_manifold(pair, true);
  PeerManifold m;
  bullet->query(0.0, m);
  ASSERT_TRUE(m.supported) << m.status;
  ASSERT_FALSE(m.points.empty());
  const ContactResult r = hedra::collision::contact(pair.a, pair.pose_a, pair.b, pair.pose_b);
  ASSERT_EQ(r.count, 4);
  EXPECT_NEAR(deepest(m), deepest(r), 1e-9);
  for (const auto& p : m.points) EXPECT_GT(p.normal.dot(r.normal), 1.0 - 1e-9);  // the adapter's convention
  // Every point Bullet reports is at one of hedra's four corners' depth.
  for (const auto& p : m.points) EXPECT_NEAR(p.depth, 0.05, 1e-9);
}

TEST(ManifoldPeer, RandomHullsDisagreementsAreDecidedByTheExactReference) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int compared = 0, disagreements = 0, hedra_outside = 0, bullet_outside = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const auto ha = t::make_hull(t::random_points(rng, 8 + trial % 30, Vec(1.0, 0.8, 0.6)));
    const auto hb = t::make_hull(t::random_points(rng, 8 + trial % 20, Vec(0.7, 0.5, 0.9)));
    const Pose pa = Pose::from_quaternion(Eigen::Quaterniond::UnitRandom(), Vec(u(rng), u(rng), u(rng)));
    const Pose pb = Pose::from_quaternion(Eigen::Quaterniond::UnitRandom(), pa.translation + 0.8 * t::random_unit(rng));
    const PeerPair pair{Polyhedron{ha}, pa, Polyhedron{hb}, pb};
    const double exact = t::signed_reference_distance(t::world_vertices(*ha, pa), t::world_vertices(*hb, pb));
    const double scale = ha->bounding_radius() + hb->bounding_radius();
    if (exact > -1e-6 * scale) continue;  // overlapping pairs only
    const ContactResult r = hedra::collision::contact(pair.a, pa, pair.b, pb);
    PeerManifold m;
    hedra::peers::prepare_bullet_manifold(pair, true)->query(0.0, m);
    ASSERT_GE(r.count, 1);
    if (m.points.empty()) continue;
    ++compared;
    const double dh = deepest(r), db = deepest(m);
    const ContactSettings settings;
    // The band a manifold's deepest depth may take: the exact depth plus
    // the face bias (hedra's contract); clipping may only lower it.
    const double tol = 1e-9 * scale, bias = settings.relative_bias * -exact + settings.absolute_bias * scale;
    const double hi = -exact + bias + tol;
    EXPECT_LE(dh, hi) << trial;
    hedra_outside += dh > hi;
    if (std::abs(dh - db) > 1e-6 * scale) {
      ++disagreements;
      bullet_outside += db > hi;
      std::printf("trial %d: exact depth %.12g, hedra %.12g, bullet %.12g%s\n", trial, -exact, dh, db,
                  db > hi ? " (bullet too deep)" : "");
    }
  }
  std::printf("%d pairs compared, %d disagreements, Bullet deeper than exact + bias in %d\n", compared, disagreements,
              bullet_outside);
  EXPECT_GT(compared, 20);
  EXPECT_EQ(hedra_outside, 0);
}

}  // namespace
