// Contact manifolds against Bullet 3.24's polyhedral path
// (btPolyhedralContactClipping::findSeparatingAxis + clipHullAgainstHull,
// double precision) on box and hull pairs, judged by the exact reference
// (qhull): 128 seeded penetrating pairs (boxes, box-hull, hulls in random
// poses; boxes resting on a face, tilted up to 1e-3 rad) and the same pairs
// moved to touching. hedra, on every case: at least one point, every point on
// both surfaces within 1e-9 of the size, the deepest within the face bias of
// the exact depth; where Bullet is exact (normal within 1e-6 rad of the unique
// exact one, deepest depth within 1e-9 of the size), hedra's normal and
// deepest depth equal Bullet's, or its face bias kept another face (no deeper
// than the overlap along it). Found (256 cases): Bullet exact in 79 (hedra
// agrees in all 79: a face kept by the bias whose clipping drops the
// incident shape's deepest vertex follows the exact normal); Bullet
// without a point on 85 of the 128 touching cases; its deepest point
// shallower than exact in 37 (worst 1.1e-4 of the size), deeper than exact
// plus the bias in 30 (worst 0.14: the clipped depths are measured along A's
// face normal whatever axis won), its normal off the exact one in 44, 338 of
// its 642 points off a surface (worst 0.32 of the size); hedra 0 of 481 off a
// surface, its deepest point never below the exact depth. Fixed seeds.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <hedra/collision/manifold.hpp>
#include <random>
#include <string>
#include <vector>

#include "../collision/collision_test_support.hpp"
#include "bullet_manifold.hpp"
#include "exact_reference.hpp"

namespace {

using hedra::collision::Box;
using hedra::collision::ContactPath;
using hedra::collision::ContactPoint;
using hedra::collision::ContactResult;
using hedra::collision::ContactSettings;
using hedra::collision::Polyhedron;
using hedra::collision::Pose;
using hedra::collision::Shape;
using hedra::peers::PeerContactPoint;
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

Shape random_box(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> axis(0.3, 1.0);
  return Box{Vec(axis(rng), axis(rng), axis(rng))};
}
Shape random_hull(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> n(8, 40);
  std::uniform_real_distribution<double> axis(0.4, 1.0);
  return Polyhedron{t::make_hull(t::random_points(rng, n(rng), Vec(axis(rng), axis(rng), axis(rng))))};
}
Pose random_pose(std::mt19937_64& rng, const Vec& at) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Pose::from_quaternion(Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized(), at);
}

// Seeded pairs: boxes, box-hull and hull pairs in random poses (B's centre
// 0.2 to 0.9 of the summed bounding radii away), and boxes resting on a
// box's face, turned about the normal, tilted by up to 1e-3 rad, 1e-4 to
// 3e-2 deep.
std::vector<PeerPair> make_pairs(int per_family) {
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> reach(0.2, 0.9), u(-1.0, 1.0), tilt(0.0, 1e-3), depth(1e-4, 3e-2);
  std::vector<PeerPair> out;
  for (int family = 0; family < 3; ++family)
    for (int i = 0; i < per_family; ++i) {
      const Shape a = family == 2 ? random_hull(rng) : random_box(rng);
      const Shape b = family == 0 ? random_box(rng) : random_hull(rng);
      const Pose pa = random_pose(rng, Vec::Zero());
      const double r = hedra::collision::bounding_radius(a) + hedra::collision::bounding_radius(b);
      out.push_back({a, pa, b, random_pose(rng, reach(rng) * r * t::random_unit(rng))});
    }
  for (int i = 0; i < per_family; ++i) {
    const Box base{Vec(1.0, 1.0, 0.5)}, top = std::get<Box>(random_box(rng));
    const Eigen::Quaterniond q = Eigen::Quaterniond(Eigen::AngleAxisd(tilt(rng), t::random_unit(rng))) *
                                 Eigen::Quaterniond(Eigen::AngleAxisd(M_PI * u(rng), Vec::UnitZ()));
    const Vec at(0.5 * u(rng), 0.5 * u(rng), 0.5 + top.half_extents.z() - depth(rng));
    out.push_back({base, Pose::identity(), top, Pose::from_quaternion(q, at)});
  }
  return out;
}

double angle(const Vec& a, const Vec& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

struct Tally {
  int cases = 0, touching = 0;
  int bullet_right = 0, hedra_agrees = 0, hedra_biased = 0;  // where Bullet is right
  int hedra_shallow = 0;
  double worst_hedra_shallow = 0.0;
  int bullet_none = 0, bullet_none_touching = 0, bullet_shallow = 0, bullet_deep = 0, bullet_normal_off = 0;
  int bullet_points = 0, bullet_off_surface = 0, hedra_points = 0, hedra_off_surface = 0;
  double worst_shallow = 0.0, worst_deep = 0.0, worst_bullet_surface = 0.0, worst_hedra_surface = 0.0;
};

// One pair: hedra's contract asserted, Bullet's answer judged by the exact
// reference and tallied.
void check(const PeerPair& p, const std::string& kind, Tally& tally) {
  const auto exact = hedra::reference::exact_signed_distance(p.a, p.pose_a, p.b, p.pose_b);
  ASSERT_TRUE(exact.ok) << exact.reason;
  const double size = hedra::collision::bounding_radius(p.a) + hedra::collision::bounding_radius(p.b);
  const double tol = exact.error_bound + 1e-9 * size;
  const double depth = -exact.distance;
  const ContactSettings settings;
  const double bias = settings.relative_bias * std::abs(depth) + settings.absolute_bias * size;
  SCOPED_TRACE(kind + " exact depth " + std::to_string(depth));
  ++tally.cases;
  // hedra: at least one point, the deepest between the exact depth and the
  // exact depth plus the face bias, every point on both surfaces.
  const ContactResult r = hedra::collision::contact(p.a, p.pose_a, p.b, p.pose_b, nullptr, settings);
  ASSERT_EQ(r.status, hedra::collision::Status::ok);
  ASSERT_GE(r.count, 1);
  double dh = -INFINITY;
  for (int k = 0; k < r.count; ++k) {
    const ContactPoint& q = r.points[k];
    dh = std::max(dh, q.depth);
    const double off = std::max(std::abs(t::surface_distance(p.a, p.pose_a, q.point + 0.5 * q.depth * r.normal)),
                                std::abs(t::surface_distance(p.b, p.pose_b, q.point - 0.5 * q.depth * r.normal)));
    ++tally.hedra_points;
    tally.hedra_off_surface += off > tol;
    tally.worst_hedra_surface = std::max(tally.worst_hedra_surface, off / size);
    EXPECT_LE(off, tol) << "hedra point " << k << " off a surface";
  }
  // The deepest point may sit below the exact depth only where a face
  // contact's deepest incident vertex was clipped away, by less than the bias
  // (manifold.hpp); counted.
  if (dh < depth - tol) {
    ++tally.hedra_shallow;
    tally.worst_hedra_shallow = std::max(tally.worst_hedra_shallow, (depth - dh) / size);
  }
  EXPECT_GE(dh, depth - bias - tol) << "hedra's deepest point shallower than the exact depth by more than the bias";
  EXPECT_LE(dh, depth + bias + tol) << "hedra's deepest point deeper than the exact depth plus the bias";

  // Bullet (double precision), points within the same touching band.
  PeerManifold m;
  hedra::peers::prepare_bullet_manifold(p, true)->query(1e-9 * size, m);
  ASSERT_TRUE(m.supported) << m.status;
  if (m.points.empty()) {
    ++tally.bullet_none;
    tally.bullet_none_touching += kind == "touching";
    return;
  }
  const PeerContactPoint* deepest = &m.points[0];
  for (const PeerContactPoint& q : m.points) {
    if (q.depth > deepest->depth) deepest = &q;
    // Bullet's point is on B, its point on A depth along the normal from it.
    const double off = std::max(std::abs(t::surface_distance(p.b, p.pose_b, q.point)),
                                std::abs(t::surface_distance(p.a, p.pose_a, q.point + q.depth * q.normal)));
    ++tally.bullet_points;
    tally.bullet_off_surface += off > tol;
    tally.worst_bullet_surface = std::max(tally.worst_bullet_surface, off / size);
  }
  const double db = deepest->depth;
  const bool normal_right = exact.normal_unique && angle(deepest->normal, exact.normal) <= 1e-6;
  tally.bullet_normal_off += exact.normal_unique && !normal_right;
  if (db < depth - tol) {
    ++tally.bullet_shallow;
    tally.worst_shallow = std::max(tally.worst_shallow, (depth - db) / size);
  }
  if (db > depth + bias + tol) {
    ++tally.bullet_deep;
    tally.worst_deep = std::max(tally.worst_deep, (db - depth) / size);
  }
  if (!normal_right || std::abs(db - depth) > tol) return;
  // Bullet right: hedra agrees, unless its face bias chose another axis
  // (then its distance lies within the bias, asserted above).
  ++tally.bullet_right;
  if (angle(r.normal, deepest->normal) > 1e-6) {
    // Another axis (a face kept where another is better by less than the
    // bias): a face contact whose points, gaps along its own normal, are no
    // deeper than the overlap along it, h_A(n) + h_B(-n) from the supports
    // (less where the deepest incident vertex lies beyond the reference face).
    ++tally.hedra_biased;
    EXPECT_TRUE(r.path == ContactPath::face_a || r.path == ContactPath::face_b) << to_string(r.path);
    const double overlap = t::support_value(p.a, p.pose_a, r.normal) + t::support_value(p.b, p.pose_b, -r.normal);
    EXPECT_LE(dh, overlap + tol) << "hedra's depth beyond the overlap along its normal";
    return;
  }
  ++tally.hedra_agrees;
  EXPECT_NEAR(dh, db, tol) << "hedra's deepest depth off Bullet's (both exact)";
}

TEST(ManifoldPeer, HedraMatchesBulletWhereBulletIsExactAndTheExactReferenceWhereBulletIsNot) {
  Tally tally;
  for (const PeerPair& p : make_pairs(40)) {
    const auto exact = hedra::reference::exact_signed_distance(p.a, p.pose_a, p.b, p.pose_b);
    ASSERT_TRUE(exact.ok) << exact.reason;
    if (!(exact.distance < 0.0)) continue;
    check(p, "penetrating", tally);
    // Touching: B moved out along the exact normal by the depth.
    PeerPair touching = p;
    touching.pose_b.translation += -exact.distance * exact.normal;
    ++tally.touching;
    check(touching, "touching", tally);
  }
  std::printf(
      "%d cases (%d touching). Bullet exact (normal within 1e-6 rad, deepest depth within 1e-9 of the size) in %d: "
      "hedra agrees in %d, its face bias chose another axis in %d.\n"
      "Bullet wrong: no point %d (%d touching), deepest shallower than exact %d (worst %.3g of the size), deeper than "
      "exact + "
      "bias %d (worst %.3g), normal off the unique exact one %d.\n"
      "Points off a surface by more than 1e-9 of the size: hedra %d of %d (worst %.3g), Bullet %d of %d (worst "
      "%.3g).\nhedra's deepest point below the exact depth (within the bias): %d (worst %.3g of the size).\n",
      tally.cases, tally.touching, tally.bullet_right, tally.hedra_agrees, tally.hedra_biased, tally.bullet_none,
      tally.bullet_none_touching, tally.bullet_shallow, tally.worst_shallow, tally.bullet_deep, tally.worst_deep,
      tally.bullet_normal_off, tally.hedra_off_surface, tally.hedra_points, tally.worst_hedra_surface,
      tally.bullet_off_surface, tally.bullet_points, tally.worst_bullet_surface, tally.hedra_shallow,
      tally.worst_hedra_shallow);
  EXPECT_GT(tally.cases, 250);
  EXPECT_GT(tally.bullet_right, 50);  // the agreement is tested on enough pairs
  EXPECT_EQ(tally.hedra_off_surface, 0);
}

}  // namespace
