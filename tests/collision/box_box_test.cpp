// The box-box contact path (collision/src/box_box.cpp) against the general
// polytope path (ContactSettings::box_box_path = false) and the exact
// reference (qhull's Minkowski difference of the corners):
//   * on random poses of nine families (tumbling, near-parallel faces,
//     crossed edges, touching, apart within the contact distance, huge and
//     tiny boxes, rounded boxes resting with their cores apart, far from the
//     origin) the two paths give the same answer
//     (status, path, points, depths, ids, normal; to 1e-12 of the size),
//     the box path answers nearly every sharp pair itself, and every
//     penetrating or touching answer is exact: each point's witnesses on
//     the two surfaces (to the clipping tolerance, 1e-6 of the size), the
//     deepest never shallower than the exact depth;
//   * frame after frame with a cache (still, jittering, sliding, turning,
//     tumbling) the box path's warm answers equal the general path's warm
//     answers, and a still pair's answer comes from the cache on >= 99 % of
//     the frames, equal bit for bit to a cold query at the new poses.
#include "../../collision/src/box_box.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <hedra/collision/manifold.hpp>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "collision_test_support.hpp"

namespace hedra::collision {
namespace {

using Vec = Eigen::Vector3d;

struct Pair {
  Box a, b;
  Pose pa, pb;
};

Pose random_pose(std::mt19937_64& rng, const Vec& t) {
  std::normal_distribution<double> g(0.0, 1.0);
  return Pose::from_quaternion(Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)), t);
}

Box random_box(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> h(0.05, 1.0);
  return Box{scale * Vec(h(rng), h(rng), h(rng)), 0.0};
}

double size_of(const Pair& p) { return p.a.half_extents.norm() + p.b.half_extents.norm(); }

std::vector<Vec> corners(const Box& b, const Pose& pose) {
  std::vector<Vec> out;
  for (int i = 0; i < 8; ++i) {
    const Vec c((i & 1) ? b.half_extents.x() : -b.half_extents.x(), (i & 2) ? b.half_extents.y() : -b.half_extents.y(),
                (i & 4) ? b.half_extents.z() : -b.half_extents.z());
    out.push_back(pose.apply(c));
  }
  return out;
}

// B moved along `n` so that the pair's penetration distance becomes `gap`.
void set_gap(Pair& p, double gap) {
  const PenetrationResult pen = penetration(p.a, p.pa, p.b, p.pb);
  ASSERT_EQ(pen.status, Status::ok);
  p.pb.translation += (gap - pen.distance) * pen.normal;
}

// Nine families of `count` pairs each.
std::vector<std::pair<std::string, Pair>> make_pairs(int count) {
  std::mt19937_64 rng(2828);
  std::uniform_real_distribution<double> u(-1.0, 1.0), small_angle(-1e-3, 1e-3);
  std::vector<std::pair<std::string, Pair>> out;
  for (int k = 0; k < count; ++k) {
    {  // tumbling, overlapping or not
      Pair p{random_box(rng, 1.0), random_box(rng, 1.0), random_pose(rng, Vec::Zero()), {}};
      p.pb = random_pose(rng, 1.2 * Vec(u(rng), u(rng), u(rng)));
      out.push_back({"tumbling", p});
    }
    {  // near-parallel faces: B on A's top face, tilted by up to 1e-3 rad, 1e-4 to 1e-2 deep
      Pair p{random_box(rng, 1.0), random_box(rng, 1.0), random_pose(rng, Vec(u(rng), u(rng), u(rng))), {}};
      const Eigen::Matrix3d tilt = Eigen::AngleAxisd(small_angle(rng), testing::random_unit(rng)).toRotationMatrix();
      const Eigen::Matrix3d yaw = Eigen::AngleAxisd(3.0 * u(rng), Vec::UnitZ()).toRotationMatrix();
      p.pb.rotation = p.pa.rotation * tilt * yaw;
      const double z = p.a.half_extents.z() + p.b.half_extents.z() - std::pow(10.0, -4.0 + 2.0 * std::abs(u(rng)));
      p.pb.translation = p.pa.apply(Vec(0.5 * u(rng) * p.a.half_extents.x(), 0.5 * u(rng) * p.a.half_extents.y(), z));
      out.push_back({"near_parallel", p});
    }
    {  // crossed edges: both boxes turned 45 degrees about two axes, edge on edge
      Pair p{random_box(rng, 1.0), random_box(rng, 1.0), Pose::identity(), {}};
      const Eigen::Matrix3d ra = Eigen::AngleAxisd(M_PI / 4 + 0.1 * u(rng), Vec::UnitX()).toRotationMatrix();
      const Eigen::Matrix3d rb = Eigen::AngleAxisd(M_PI / 4 + 0.1 * u(rng), Vec::UnitY()).toRotationMatrix();
      p.pa.rotation = ra;
      p.pb = Pose{rb, Vec(0.1 * u(rng), 0.1 * u(rng), 2.0)};
      set_gap(p, -1e-3 * (1.0 + u(rng)));
      out.push_back({"crossed_edges", p});
    }
    {  // touching
      Pair p{random_box(rng, 1.0), random_box(rng, 1.0), random_pose(rng, Vec::Zero()), random_pose(rng, Vec::Zero())};
      p.pb.translation = 0.5 * Vec(u(rng), u(rng), u(rng));
      set_gap(p, 0.0);
      out.push_back({"touching", p});
    }
    {  // apart within the contact distance (0.05 of the size)
      Pair p{random_box(rng, 1.0), random_box(rng, 1.0), random_pose(rng, Vec::Zero()), random_pose(rng, Vec::Zero())};
      p.pb.translation = 0.5 * Vec(u(rng), u(rng), u(rng));
      set_gap(p, 0.04 * std::abs(u(rng)));
      out.push_back({"apart", p});
    }
    {  // huge
      Pair p{random_box(rng, 1e4), random_box(rng, 1e4), random_pose(rng, Vec::Zero()), {}};
      p.pb = random_pose(rng, 1.2e4 * Vec(u(rng), u(rng), u(rng)));
      out.push_back({"huge", p});
    }
    {  // tiny
      Pair p{random_box(rng, 1e-4), random_box(rng, 1e-4), random_pose(rng, Vec::Zero()), {}};
      p.pb = random_pose(rng, 1.2e-4 * Vec(u(rng), u(rng), u(rng)));
      out.push_back({"tiny", p});
    }
    {  // rounded boxes resting tilted on a rounded box, their cores apart
      Pair p{random_box(rng, 1.0), random_box(rng, 1.0), random_pose(rng, Vec(u(rng), u(rng), u(rng))), {}};
      p.a.margin = 0.05 * (1.0 + u(rng));
      p.b.margin = 0.05 * (1.0 + u(rng));
      const Eigen::Matrix3d tilt = Eigen::AngleAxisd(small_angle(rng), testing::random_unit(rng)).toRotationMatrix();
      p.pb.rotation = p.pa.rotation * tilt * Eigen::AngleAxisd(3.0 * u(rng), Vec::UnitZ()).toRotationMatrix();
      const double z = p.a.half_extents.z() + p.b.half_extents.z() + p.a.margin + p.b.margin - 1e-3 * (1.0 + u(rng));
      p.pb.translation = p.pa.apply(Vec(0.5 * u(rng) * p.a.half_extents.x(), 0.5 * u(rng) * p.a.half_extents.y(), z));
      out.push_back({"rounded_resting", p});
    }
    {  // far from the origin, resting tilted
      const Vec far(3e5, -2e5, 1e5);
      Pair p{random_box(rng, 1.0), random_box(rng, 1.0), Pose{Eigen::Matrix3d::Identity(), far}, {}};
      const Eigen::Matrix3d tilt = Eigen::AngleAxisd(small_angle(rng), testing::random_unit(rng)).toRotationMatrix();
      p.pb = Pose{tilt * Eigen::AngleAxisd(u(rng), Vec::UnitZ()).toRotationMatrix(),
                  far + Vec(0.3 * u(rng), 0.3 * u(rng), p.a.half_extents.z() + p.b.half_extents.z() - 1e-3)};
      out.push_back({"far", p});
    }
  }
  return out;
}

ContactSettings general(ContactSettings s) {
  s.box_box_path = false;
  return s;
}

void expect_same(const ContactResult& x, const ContactResult& y, double size, const std::string& what) {
  SCOPED_TRACE(what + ": paths " + to_string(x.path) + " / " + to_string(y.path));
  const double tol = 1e-12 * size;
  ASSERT_EQ(x.status, y.status);
  ASSERT_EQ(x.path, y.path);
  ASSERT_EQ(x.count, y.count);
  EXPECT_EQ(x.intersecting, y.intersecting);
  EXPECT_NEAR(x.distance, y.distance, tol);
  EXPECT_LE((x.normal - y.normal).norm(), 1e-12);
  // The same points (in either order: equally deep points, a resting face's
  // corners, are ordered by rounding).
  for (int k = 0; k < x.count; ++k) {
    bool found = false;
    for (int j = 0; j < y.count; ++j)
      found = found || ((x.points[k].point - y.points[j].point).norm() <= tol &&
                        std::abs(x.points[k].depth - y.points[j].depth) <= tol && x.points[k].id == y.points[j].id);
    EXPECT_TRUE(found) << "point " << k << " depth " << x.points[k].depth;
  }
}

TEST(BoxBox, TheBoxPathGivesTheGeneralPathsAnswersAndTheyAreExact) {
  const auto pairs = make_pairs(60);
  std::map<std::string, int> answered, total, exact_checked;
  double worst_surface = 0.0, worst_below = 0.0;
  for (const auto& [family, p] : pairs) {
    SCOPED_TRACE(family);
    const double size = size_of(p);
    ContactSettings s;
    s.contact_distance = family == "apart" ? 0.05 * size : 0.0;
    const ContactResult fast = contact(p.a, p.pa, p.b, p.pb, nullptr, s);
    const ContactResult slow = contact(p.a, p.pa, p.b, p.pb, nullptr, general(s));
    expect_same(fast, slow, size, family);
    ContactResult direct;
    ++total[family];
    answered[family] += detail::box_box_contact(p.a, p.pa, p.b, p.pb, nullptr, s, direct);
    if (fast.count == 0) continue;
    // Exactness against qhull's Minkowski difference of the corners.
    const double exact = testing::signed_reference_distance(corners(p.a, p.pa), corners(p.b, p.pb));
    double deepest = -INFINITY;
    for (int k = 0; k < fast.count; ++k) {
      const ContactPoint& q = fast.points[k];
      const Vec on_a = q.point + 0.5 * q.depth * fast.normal, on_b = q.point - 0.5 * q.depth * fast.normal;
      const double ea = std::abs(testing::surface_distance(p.a, p.pa, on_a));
      const double eb = std::abs(testing::surface_distance(p.b, p.pb, on_b));
      worst_surface = std::max({worst_surface, ea / size, eb / size});
      EXPECT_LE(ea, 1e-6 * size) << "point " << k << " off A";
      EXPECT_LE(eb, 1e-6 * size) << "point " << k << " off B";
      deepest = std::max(deepest, q.depth);
    }
    if (p.a.margin + p.b.margin == 0.0 && exact <= 1e-9 * size) {  // sharp, penetrating or touching
      ++exact_checked[family];
      worst_below = std::max(worst_below, (-exact - deepest) / size);
      EXPECT_LE(-exact - deepest, 1e-9 * size) << "deepest point shallower than the exact depth " << -exact;
    }
  }
  for (const auto& [family, n] : total) {
    // Sharp boxes: the box path answers all but the rare pair whose deepest
    // corner the clipping removes (penetration()'s point).
    EXPECT_GE(answered[family], 0.9 * n) << family;
  }
  EXPECT_GE(exact_checked["near_parallel"], 50);
  EXPECT_GE(exact_checked["crossed_edges"], 50);
  EXPECT_GE(exact_checked["touching"], 50);
  RecordProperty("worst_surface", std::to_string(worst_surface));
  RecordProperty("worst_below_exact", std::to_string(worst_below));
}

// Poses of B over 300 frames for each motion, A fixed.
std::vector<std::pair<std::string, std::vector<Pose>>> motions(const Box& a, const Box& b) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double z = a.half_extents.z() + b.half_extents.z() - 1e-3;
  std::vector<std::pair<std::string, std::vector<Pose>>> out;
  const auto yawed = [](double yaw, const Vec& t) {
    return Pose{Eigen::AngleAxisd(yaw, Vec::UnitZ()).toRotationMatrix(), t};
  };
  std::vector<Pose> still, jitter, slide, turn, tumble;
  Eigen::Quaterniond q = Eigen::Quaterniond::UnitRandom();
  for (int k = 0; k < 300; ++k) {
    still.push_back(yawed(0.3, Vec(0.05, -0.03, z)));
    jitter.push_back(yawed(0.3 + 1e-6 * u(rng), Vec(0.05, -0.03, z) + 1e-6 * Vec(u(rng), u(rng), u(rng))));
    slide.push_back(yawed(0.3, Vec(-0.4 + 0.003 * k, -0.03, z)));
    turn.push_back(yawed(0.3 + 0.01 * k, Vec(0.05, -0.03, z)));
    q = (q * Eigen::Quaterniond(Eigen::AngleAxisd(0.02, Vec(1, 2, 3).normalized()))).normalized();
    tumble.push_back(Pose::from_quaternion(q, Vec(0.3 * std::sin(0.01 * k), 0.2, 0.9 + 0.2 * std::cos(0.013 * k))));
  }
  out.push_back({"still", still});
  out.push_back({"jitter", jitter});
  out.push_back({"slide", slide});
  out.push_back({"turn", turn});
  out.push_back({"tumble", tumble});
  return out;
}

// Warm answers (one cache across the frames) against cold ones at the same
// poses: the same status and points' presence, the distance within the face
// bias (the cache keeps last frame's reference face of B while it holds), the
// same normal and points when the same reference face was chosen, and every
// warm point exact at the new poses (witnesses on both surfaces).
TEST(BoxBox, WarmAnswersAreColdAnswersAtTheNewPosesButForTheKeptFace) {
  const Box unit{Vec(0.5, 0.5, 0.5), 0.0}, plate{Vec(0.5, 0.5, 0.005), 0.0}, small{Vec(0.01, 0.01, 0.01), 0.0};
  const std::pair<Box, Box> shapes[] = {{unit, unit}, {plate, plate}, {unit, small}, {small, unit}};
  int frames = 0, same_axis = 0;
  for (const auto& [a, b] : shapes)
    for (const auto& [motion, poses] : motions(a, b)) {
      ContactCache cache;
      const ContactSettings s;
      const double size = a.half_extents.norm() + b.half_extents.norm();
      for (std::size_t k = 0; k < poses.size(); ++k) {
        SCOPED_TRACE(motion + " frame " + std::to_string(k));
        const ContactResult warm = contact(a, Pose::identity(), b, poses[k], &cache, s);
        const ContactResult cold = contact(a, Pose::identity(), b, poses[k], nullptr, s);
        ++frames;
        ASSERT_EQ(warm.status, cold.status);
        ASSERT_EQ(warm.count > 0, cold.count > 0);
        const double bias = s.relative_bias * std::abs(cold.distance) + s.absolute_bias * size + 1e-12 * size;
        EXPECT_LE(std::abs(warm.distance - cold.distance), bias);
        const bool same = warm.path == cold.path && warm.count == cold.count &&
                          (warm.count == 0 || warm.points[0].id.reference == cold.points[0].id.reference);
        if (same) {
          ++same_axis;
          EXPECT_LE((warm.normal - cold.normal).norm(), 1e-12);
          EXPECT_NEAR(warm.distance, cold.distance, 1e-12 * size);
        }
        for (int i = 0; i < warm.count; ++i) {
          const ContactPoint& q = warm.points[i];
          const Vec on_a = q.point + 0.5 * q.depth * warm.normal, on_b = q.point - 0.5 * q.depth * warm.normal;
          EXPECT_LE(std::abs(testing::surface_distance(a, Pose::identity(), on_a)), 1e-6 * size);
          EXPECT_LE(std::abs(testing::surface_distance(b, poses[k], on_b)), 1e-6 * size);
        }
        if (HasFailure()) return;
      }
    }
  EXPECT_EQ(frames, 4 * 5 * 300);
  EXPECT_GE(same_axis, 0.9 * frames);
}

TEST(BoxBox, AStillPairIsAnsweredFromItsCacheAtTheNewPosesBitForBit) {
  const Box a{Vec(0.5, 0.5, 0.5), 0.0}, b{Vec(0.5, 0.5, 0.5), 0.0};
  ContactCache cache;
  int hits = 0;
  const int frames = 1000;
  for (int k = 0; k < frames; ++k) {
    // Both bodies moved by the same whole number: the relative pose is the
    // same bit for bit, the world poses are not.
    const Vec shift(static_cast<double>(k % 7), -static_cast<double>(k % 5), 0.0);
    const Pose pa{Eigen::Matrix3d::Identity(), shift};
    const Pose pb{Eigen::AngleAxisd(0.3, Vec::UnitZ()).toRotationMatrix(), shift + Vec(0.0625, -0.03125, 0.999)};
    const ContactResult warm = contact(a, pa, b, pb, &cache);
    const ContactResult cold = contact(a, pa, b, pb);
    hits += warm.stats.cache_hit;
    ASSERT_EQ(warm.count, cold.count);
    ASSERT_EQ(warm.count, 4);
    EXPECT_EQ(warm.distance, cold.distance);
    EXPECT_EQ(warm.normal, cold.normal);
    EXPECT_EQ(warm.point_a, cold.point_a);
    for (int i = 0; i < warm.count; ++i) {
      EXPECT_EQ(warm.points[i].point, cold.points[i].point);
      EXPECT_EQ(warm.points[i].depth, cold.points[i].depth);
      EXPECT_TRUE(warm.points[i].id == cold.points[i].id);
    }
  }
  EXPECT_GE(hits, 0.99 * frames);
  // Moved by a hair: rebuilt, not recycled.
  const Pose pb{Eigen::AngleAxisd(0.3, Vec::UnitZ()).toRotationMatrix(), Vec(0.0625, -0.03125, 0.999 + 1e-12)};
  EXPECT_FALSE(contact(a, Pose::identity(), b, pb, &cache).stats.cache_hit);
  // Another contact distance: rebuilt.
  ContactSettings s;
  s.contact_distance = 0.01;
  EXPECT_FALSE(contact(a, Pose::identity(), b, pb, &cache, s).stats.cache_hit);
}

}  // namespace
}  // namespace hedra::collision
