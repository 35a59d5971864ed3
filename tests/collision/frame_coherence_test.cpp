// Caches never change an answer: penetration() and contact() with their
// per-pair caches (GjkCache, ContactCache) carried along smooth trajectories
// (tools/microbench/trajectories.hpp: 1 % of the size and 1 degree a frame;
// separated, touching, slightly penetrating; boxes, a box sliding on a
// plate, hulls of 8 to 128 vertices, rounded boxes and hulls) answer as the
// same queries without a cache:
//   * penetration(): the same signed distance within the error bounds;
//   * contact(): the same status, point count and signed distance, and the
//     same path, except where the cached reference face keeps B's face that
//     a cold query (A's face first) replaces by A's (both within the bias of
//     the exact depth), and where the cached separating face answers alone
//     (separated either way; the cached axis's distance is a lower bound
//     on the exact one, as a cold SAT's is).
#include <gtest/gtest.h>

#include <hedra/collision/manifold.hpp>

#include "../../tools/microbench/trajectories.hpp"

namespace hedra::collision {
namespace {

struct Tally {
  int frames = 0, kept_face_b = 0, cached_separated = 0, cached_face = 0;
};

void check_trajectory(const trajectories::Trajectory& t, const std::string& what, Tally& tally) {
  GjkCache gjk;
  ContactCache cache;
  const ContactSettings settings;
  const double tol = 1e-9 * t.size;
  for (std::size_t f = 0; f < t.pose_b.size(); ++f) {
    SCOPED_TRACE(what + " frame " + std::to_string(f));
    const Pose& pb = t.pose_b[f];
    const PenetrationResult pc = penetration(t.a, t.pose_a, t.b, pb);
    const PenetrationResult pw = penetration(t.a, t.pose_a, t.b, pb, &gjk);
    ASSERT_EQ(pc.status, Status::ok);
    ASSERT_EQ(pw.status, Status::ok);
    EXPECT_NEAR(pw.distance, pc.distance, pc.error_bound + pw.error_bound + tol);

    const ContactResult cc = contact(t.a, t.pose_a, t.b, pb, nullptr, settings);
    const ContactResult cw = contact(t.a, t.pose_a, t.b, pb, &cache, settings);
    ++tally.frames;
    ASSERT_EQ(cw.status, cc.status);
    if (std::abs(cc.distance) > pc.error_bound + tol) {  // touching: either sign
      EXPECT_EQ(cw.intersecting, cc.intersecting);
    }
    ASSERT_EQ(cw.count, cc.count);
    if (cw.stats.cache_hit && cw.path == ContactPath::separated) {
      ++tally.cached_separated;
      EXPECT_EQ(cc.path, ContactPath::separated);
      EXPECT_EQ(cw.path, ContactPath::separated);
      EXPECT_LE(cw.distance, pc.distance + tol);  // a lower bound on the distance, as a cold SAT's
      EXPECT_GT(cw.distance, settings.contact_distance);
      continue;
    }
    tally.cached_face += cw.stats.cache_hit;
    const double bias = settings.relative_bias * std::abs(pc.distance) + settings.absolute_bias * t.size;
    if (cw.path == ContactPath::face_b && cc.path == ContactPath::face_a) {
      ++tally.kept_face_b;
      EXPECT_LE(std::abs(cw.distance - cc.distance), bias + tol);
      continue;
    }
    EXPECT_EQ(cw.path, cc.path);
    EXPECT_NEAR(cw.distance, cc.distance, pc.error_bound + tol);
    for (int k = 0; k < cw.count; ++k) {
      EXPECT_NEAR(cw.points[k].depth, cc.points[k].depth, pc.error_bound + tol);
      EXPECT_LE((cw.points[k].point - cc.points[k].point).norm(), 1e-6 * t.size);
    }
  }
}

TEST(FrameCoherence, WarmAnswersEqualColdOnes) {
  Tally tally;
  const char* shapes[] = {"box", "box_resting", "hull8", "hull32", "hull128", "rounded_box", "rounded_hull32"};
  const std::pair<const char*, double> kinds[] = {{"separated", 0.02}, {"touching", 0.0}, {"penetrating", -0.01}};
  std::uint64_t seed = 7;
  for (const char* shape : shapes)
    for (const auto& [kind, target] : kinds)
      for (const trajectories::Trajectory& t : trajectories::make_trajectories(shape, target, 3, 60, ++seed))
        check_trajectory(t, std::string(shape) + " " + kind, tally);
  std::printf(
      "frames %d, B's face kept by the cache %d, separated by the cached axis %d, built on the cached face %d\n",
      tally.frames, tally.kept_face_b, tally.cached_separated, tally.cached_face);
  EXPECT_EQ(tally.frames, 7 * 3 * 3 * 60);
  EXPECT_GT(tally.cached_separated, 100);  // the separated trajectories use the cache
}

}  // namespace
}  // namespace hedra::collision
