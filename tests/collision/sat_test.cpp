// SAT between polyhedra (sat.hpp): for overlapping pairs its largest
// separation must equal the brute-force SAT over every face normal and every
// edge-pair cross product (each axis measured by projecting all vertices, as
// Bullet does) and minus the exact penetration depth of the Minkowski
// difference (qhull reference); for separated pairs it is positive and a
// lower bound of the exact distance. The Gauss-map test must prune
// most edge pairs. Fixed seeds.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <hedra/collision/detail/sat.hpp>
#include <random>

#include "collision_test_support.hpp"

namespace hedra::collision {
namespace {

using testing::make_hull;
using testing::random_points;
using testing::random_unit;
using Vec = Eigen::Vector3d;

// Brute force: every face normal of both and every cross product of edge
// directions, each axis measured on all vertices.
double brute_force_separation(const ConvexPolyhedron& a, const Pose& pa, const ConvexPolyhedron& b, const Pose& pb) {
  const std::vector<Vec> va = testing::world_vertices(a, pa), vb = testing::world_vertices(b, pb);
  auto separation = [&](Vec n) -> double {
    if (!(n.norm() > 0)) return -INFINITY;
    n.normalize();
    double max_a = -INFINITY, min_a = INFINITY, max_b = -INFINITY, min_b = INFINITY;
    for (const Vec& v : va) max_a = std::max(max_a, n.dot(v)), min_a = std::min(min_a, n.dot(v));
    for (const Vec& v : vb) max_b = std::max(max_b, n.dot(v)), min_b = std::min(min_b, n.dot(v));
    return std::max(min_b - max_a, min_a - max_b);
  };
  double best = -INFINITY;
  std::vector<Vec> ea, eb;
  for (hull::Index f = 0; f < a.mesh().face_count(); ++f)
    best = std::max(best, separation(pa.rotation * a.mesh().plane(f).normal));
  for (hull::Index f = 0; f < b.mesh().face_count(); ++f)
    best = std::max(best, separation(pb.rotation * b.mesh().plane(f).normal));
  for (hull::Index e = 0; e < a.mesh().half_edge_count(); ++e) ea.push_back(pa.rotation * a.mesh().edge_vector(e));
  for (hull::Index e = 0; e < b.mesh().half_edge_count(); ++e) eb.push_back(pb.rotation * b.mesh().edge_vector(e));
  for (const Vec& x : ea)
    for (const Vec& y : eb) {
      const Vec n = x.cross(y);
      if (n.norm() > 1e-3 * x.norm() * y.norm()) best = std::max(best, separation(n));
    }
  return best;
}

double sat_separation(const SatResult& s) {
  return std::max({s.face_a.separation, s.face_b.separation, s.edge.separation});
}

TEST(Sat, MatchesBruteForceAndExactDepthOnRandomHulls) {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int overlapping = 0, separated = 0, pruned_pairs = 0, all_pairs = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const auto ha = make_hull(random_points(rng, 16 + trial % 20, Vec(1.0, 0.7, 0.5)));
    const auto hb = make_hull(random_points(rng, 12 + trial % 17, Vec(0.6, 0.9, 0.4)));
    const Pose pa = Pose::from_quaternion(Eigen::Quaterniond::UnitRandom(), Vec(u(rng), u(rng), u(rng)));
    const Pose pb = Pose::from_quaternion(Eigen::Quaterniond::UnitRandom(), pa.translation + 1.2 * random_unit(rng));
    const SatPolytope a = sat_polytope(*ha), b = sat_polytope(*hb);
    const RelativePose rel = relative_pose(pa, ha->offset(), pb, hb->offset());
    SatSettings settings;
    settings.early_out = INFINITY;  // the full test
    const SatResult s = sat_query(a, b, rel, settings);
    const double sep = sat_separation(s);
    const double scale = ha->bounding_radius() + hb->bounding_radius();
    const double brute = brute_force_separation(*ha, pa, *hb, pb);
    EXPECT_LE(sep, brute + 1e-9 * scale) << "trial " << trial;  // a subset of the brute-force axes
    const double exact =
        testing::signed_reference_distance(testing::world_vertices(*ha, pa), testing::world_vertices(*hb, pb));
    if (exact < -1e-6 * scale) {
      ++overlapping;
      // Overlapping: the Minkowski faces hold the minimum, so the pruned
      // test loses nothing against the brute force and both are exact.
      EXPECT_NEAR(sep, brute, 1e-9 * scale) << "trial " << trial;
      EXPECT_NEAR(sep, exact, 1e-9 * scale) << "trial " << trial;
    } else if (exact > 1e-6 * scale) {
      ++separated;
      EXPECT_GT(sep, 0.0) << "trial " << trial;
      EXPECT_LE(sep, exact + 1e-9 * scale) << "trial " << trial;  // a lower bound of the distance
    }
    pruned_pairs += s.edge_pairs;
    all_pairs += static_cast<int>(ha->mesh().edge_count() * hb->mesh().edge_count());
  }
  EXPECT_GT(overlapping, 10);
  EXPECT_GT(separated, 10);
  EXPECT_LT(pruned_pairs * 5, all_pairs);  // the Gauss map keeps a small fraction
}

TEST(Sat, LargeHullsWalkTheMeshAndStayExact) {
  // Above 512 edges A's edges are not gathered on the stack: the mesh walk.
  std::mt19937_64 rng(4);
  std::vector<Vec> sphere;
  for (int i = 0; i < 300; ++i) sphere.push_back(random_unit(rng));
  const auto ha = make_hull(sphere);
  ASSERT_GT(ha->mesh().edge_count(), 512u);
  int overlapping = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const auto hb = make_hull(random_points(rng, 20, Vec(0.6, 0.4, 0.5)));
    const Pose pa = Pose::from_quaternion(Eigen::Quaterniond::UnitRandom(), Vec::Zero());
    const Pose pb = Pose::from_quaternion(Eigen::Quaterniond::UnitRandom(), 1.1 * random_unit(rng));
    SatSettings settings;
    settings.early_out = INFINITY;
    const SatResult s =
        sat_query(sat_polytope(*ha), sat_polytope(*hb), relative_pose(pa, ha->offset(), pb, hb->offset()), settings);
    const double exact =
        testing::signed_reference_distance(testing::world_vertices(*ha, pa), testing::world_vertices(*hb, pb));
    if (exact < -1e-6) {
      ++overlapping;
      EXPECT_NEAR(sat_separation(s), exact, 1e-9) << trial;
    }
  }
  EXPECT_GT(overlapping, 2);
}

TEST(Sat, BoxesUseTheSharedTopologyAndEarlyOut) {
  const hull::HalfEdgeMesh& mesh = unit_box_mesh();
  ASSERT_TRUE(mesh.validate().ok()) << mesh.validate().to_string();
  EXPECT_EQ(mesh.vertex_count(), 8u);
  EXPECT_EQ(mesh.face_count(), 6u);
  BoxPolytopeStorage sa, sb;
  const SatPolytope a = sat_polytope(Box{{1.0, 2.0, 3.0}}, sa), b = sat_polytope(Box{{0.5, 0.5, 0.5}}, sb);
  // B 0.25 above A's top face (z = 3), turned about z: face axis of A, gap 0.25.
  const Pose pa = Pose::identity();
  const Pose pb = Pose::from_quaternion(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Vec::UnitZ())), Vec(0.2, 0.1, 3.75));
  const RelativePose rel = relative_pose(pa, Vec::Zero(), pb, Vec::Zero());
  SatSettings settings;
  settings.early_out = INFINITY;
  const SatResult full = sat_query(a, b, rel, settings);
  EXPECT_FALSE(full.separated);
  EXPECT_NEAR(full.face_a.separation, 0.25, 1e-14);
  EXPECT_EQ(full.face_a.normal, Vec(0, 0, 1));
  settings.early_out = 0.1;
  const SatResult early = sat_query(a, b, rel, settings);
  EXPECT_TRUE(early.separated);
  // Support of a box follows its sign bits.
  EXPECT_EQ(b.support(Vec(1, -1, 1)), 5u);
  EXPECT_EQ(b.vertex(5), Vec(0.5, -0.5, 0.5));
}

TEST(Sat, RandomBoxPairsMatchTheExactDepth) {
  // Two boxes take the closed-form path (face axes and the 3 x 3 edge axes).
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(0.2, 1.0);
  int overlapping = 0, edges = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const Vec ha(u(rng), u(rng), u(rng)), hb(u(rng), u(rng), u(rng));
    const Pose pa = Pose::from_quaternion(Eigen::Quaterniond::UnitRandom(), Vec(u(rng), u(rng), u(rng)));
    const Pose pb = Pose::from_quaternion(Eigen::Quaterniond::UnitRandom(), pa.translation + 1.3 * random_unit(rng));
    BoxPolytopeStorage sa, sb;
    const SatPolytope a = sat_polytope(Box{ha}, sa), b = sat_polytope(Box{hb}, sb);
    SatSettings settings;
    settings.early_out = INFINITY;
    const SatResult s = sat_query(a, b, relative_pose(pa, Vec::Zero(), pb, Vec::Zero()), settings);
    std::vector<Vec> va, vb;
    for (int i = 0; i < 8; ++i) {
      va.push_back(pa.apply(a.vertex(static_cast<hull::Index>(i))));
      vb.push_back(pb.apply(b.vertex(static_cast<hull::Index>(i))));
    }
    const double exact = testing::signed_reference_distance(va, vb);
    const double scale = ha.norm() + hb.norm();
    const double sep = sat_separation(s);
    if (exact < -1e-6 * scale) {
      ++overlapping;
      edges += s.edge.separation > std::max(s.face_a.separation, s.face_b.separation);
      EXPECT_NEAR(sep, exact, 1e-9 * scale) << "trial " << trial;
      if (s.edge.kind == SatAxisKind::edge) {
        // The reported edges realise the edge axis: both lie on it, A's at its top.
        const hull::HalfEdgeMesh& m = unit_box_mesh();
        const Vec n = s.edge.normal;
        const Vec a0 = a.vertex(m.origin(s.edge.feature_a)), a1 = a.vertex(m.destination(s.edge.feature_a));
        double top = -INFINITY;
        for (int i = 0; i < 8; ++i) top = std::max(top, n.dot(a.vertex(static_cast<hull::Index>(i))));
        EXPECT_NEAR(n.dot(a0), top, 1e-12 * scale);
        EXPECT_NEAR(n.dot(a1), top, 1e-12 * scale);
      }
    } else if (exact > 1e-6 * scale) {
      EXPECT_GT(sep, 0.0) << "trial " << trial;
      EXPECT_LE(sep, exact + 1e-9 * scale) << "trial " << trial;
    }
  }
  EXPECT_GT(overlapping, 30);
  EXPECT_GT(edges, 3);
}

}  // namespace
}  // namespace hedra::collision
