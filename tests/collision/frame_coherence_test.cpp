// Caches never change an answer: penetration() and contact() with their
// per-pair caches (GjkCache, ContactCache) carried along smooth trajectories
// (tools/microbench/trajectories.hpp: 1 % of the size and 1 degree a frame;
// separated, touching, slightly penetrating; boxes, a box sliding on a
// plate, hulls of 8 to 128 vertices, rounded boxes and hulls) answer as the
// same queries without a cache, and neither's deepest point is shallower
// than the exact depth:
//   * penetration(): the same signed distance within the error bounds;
//   * contact(): the same status, signed distance, path and points,
//     except where the cached reference face keeps B's face that a cold
//     query (A's face first) replaces (both within the bias of the exact
//     depth), where two axes tie within the bias (under 1 % of the frames:
//     the start of a support's climb decides), where the cache holds the
//     last frame's four points of a face with more candidates (their
//     deepest within ContactSettings::hold of the deepest candidate: the
//     distance within that of the cold one), and where the
//     cached separating axis answers alone
//     (separated either way; the cached axis's distance is a lower bound
//     on the exact one, as a cold SAT's is).
#include <gtest/gtest.h>

#include <cmath>
#include <hedra/collision/manifold.hpp>

#include "../../tools/microbench/trajectories.hpp"

namespace hedra::collision {
namespace {

struct Tally {
  int frames = 0, kept_face_b = 0, cached_separated = 0, cached_face = 0, ties = 0, held = 0;
};

// r's points have exactly the ids ids[0, n) (in any order).
bool has_ids(const ContactResult& r, const FeatureId* ids, int n) {
  if (r.count != n) return false;
  for (int k = 0; k < n; ++k) {
    bool found = false;
    for (int j = 0; j < n; ++j) found = found || r.points[j].id == ids[k];
    if (!found) return false;
  }
  return true;
}

// The cache held B's face, and the warm query kept it as the reference.
bool kept_face_b(const ContactCache& before, const ContactResult& warm) {
  return before.axis == SatAxisKind::face_b && warm.path == ContactPath::face_b && warm.count > 0 &&
         warm.points[0].id.reference == before.feature;
}

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
    const ContactCache before = cache;
    const ContactResult cw = contact(t.a, t.pose_a, t.b, pb, &cache, settings);
    ++tally.frames;
    ASSERT_EQ(cw.status, cc.status);
    if (std::abs(cc.distance) > pc.error_bound + tol) {  // touching: either sign
      EXPECT_EQ(cw.intersecting, cc.intersecting);
    }
    if (cw.stats.cache_hit && cw.path == ContactPath::separated) {
      ++tally.cached_separated;
      EXPECT_EQ(cc.path, ContactPath::separated);
      EXPECT_EQ(cw.count, 0);
      EXPECT_EQ(cc.count, 0);
      EXPECT_LE(cw.distance, pc.distance + tol);  // a lower bound on the distance, as a cold SAT's
      EXPECT_GT(cw.distance, settings.contact_distance);
      continue;
    }
    tally.cached_face += cw.stats.cache_hit;
    // Warm or cold, the deepest point is never shallower than the exact
    // depth (a face whose deepest incident vertex is clipped away gives way
    // to penetration()'s point).
    if (pc.distance <= tol) {
      for (const ContactResult* r : {&cc, &cw}) {
        double deepest = -INFINITY;
        for (int k = 0; k < r->count; ++k) deepest = std::max(deepest, r->points[k].depth);
        const double held = r == &cw ? settings.hold * t.size : 0.0;
        EXPECT_GE(deepest, -pc.distance - (pc.error_bound + tol + held)) << (r == &cw ? "warm" : "cold");
      }
    }
    const double bias = settings.relative_bias * std::abs(pc.distance) + settings.absolute_bias * t.size;
    if (kept_face_b(before, cw) && cc.path != ContactPath::face_b) {
      ++tally.kept_face_b;
      EXPECT_GE(cw.count, 1);
      EXPECT_LE(std::abs(cw.distance - cc.distance), bias + tol);
      continue;
    }
    if (cw.path != cc.path) {
      // Ties: two axes within the bias (or exact to rounding: a touching
      // vertex on an edge, say) that the start of a support's climb (the
      // cached vertex, or vertex 0) decides; either manifold is the pair's.
      ++tally.ties;
      EXPECT_GE(cw.count, 1);
      EXPECT_LE(std::abs(cw.distance - cc.distance), bias + tol);
      continue;
    }
    FeatureId cold_ids[kMaxContactPoints];
    for (int k = 0; k < cc.count; ++k) cold_ids[k] = cc.points[k].id;
    if (has_ids(cw, before.kept.data(), before.kept_count) && !has_ids(cw, cold_ids, cc.count)) {
      // The last frame's four points held (ContactSettings::hold).
      ++tally.held;
      EXPECT_LE(std::abs(cw.distance - cc.distance), settings.hold * t.size + pc.error_bound + tol);
      continue;
    }
    EXPECT_NEAR(cw.distance, cc.distance, pc.error_bound + tol);
    ASSERT_EQ(cw.count, cc.count);
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
      "frames %d, B's face kept by the cache %d, separated by the cached axis %d, built on the cached axis %d, "
      "ties %d, last frame's points held %d\n",
      tally.frames, tally.kept_face_b, tally.cached_separated, tally.cached_face, tally.ties, tally.held);
  EXPECT_LT(tally.ties, tally.frames / 100);
  EXPECT_GT(tally.cached_face, 1000);  // resting and sliding pairs skip SAT and GJK/EPA
  EXPECT_EQ(tally.frames, 7 * 3 * 3 * 60);
  EXPECT_GT(tally.cached_separated, 100);  // the separated trajectories use the cache
}

}  // namespace
}  // namespace hedra::collision
