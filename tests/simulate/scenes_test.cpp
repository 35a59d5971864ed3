// hedra inside a real simulator: with hedra as the convex-convex
// narrowphase of Bullet's btDiscreteDynamicsWorld (scenes.hpp: 60 Hz, 50
// solver iterations, friction anchors, Bullet's default sleeping), each scene
// runs 10 s of simulated time and must end at rest and unbroken:
//   * stack (10 unit boxes) and 4-level pyramid: the top box drifts sideways
//     by less than 1% of its size;
//   * every scene: no pair of bodies (ground included) interpenetrates deeper
//     than 1% of the smaller one's size, measured by the exact reference
//     (tools/reference, independent of hedra's GJK/EPA/SAT), and every body
//     has gone to sleep (Bullet deactivates a body after 2 s below its
//     sleeping thresholds);
//   * pile (20 seeded random hulls dropped on the ground): every hull ends
//     above the ground's top within 1% of its size, and no pair deeper than
//     0.05% (friction anchors held at the old contact's depth let it sink
//     0.2%; Bullet's narrowphase, 0.12%).
// hedra must have answered the pairs (its query counter moves by at least
// one query per body and step while awake). Bullet's own narrowphase runs
// the same scene and is printed beside it, not asserted.
#include "simulate/scenes.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "simulate/hedra_collision_algorithm.hpp"

namespace {

using namespace hedra::simulate;

SceneReport run(SceneKind scene, Narrowphase narrowphase) {
  SceneSettings settings;
  settings.scene = scene;
  settings.narrowphase = narrowphase;
  settings.seconds = 10.0;
  const SceneReport r = run_scene(settings);
  std::printf(
      "%s %s: top drift %.3g m, late creep %.3g m, max penetration %.3g%%, lowest above ground %.3g%%, asleep %d/%d, "
      "%.2f points/manifold, median step %.0f us\n",
      to_string(scene), to_string(narrowphase), r.top_drift, r.late_creep, 100 * r.max_penetration,
      100 * r.lowest_above_ground, r.asleep, r.bodies, r.points_per_manifold, r.median_step_us);
  return r;
}

void expect_at_rest_and_unbroken(const SceneReport& r) {
  EXPECT_EQ(r.measure_failures, 0);
  EXPECT_LT(r.max_penetration, 0.01);
  EXPECT_GT(r.lowest_above_ground, -0.01);
  EXPECT_EQ(r.asleep, r.bodies);
  EXPECT_EQ(r.max_speed, 0.0);  // Bullet zeroes a sleeping body's velocity
}

TEST(SimulateScenes, TenBoxStackStands) {
  const SceneReport r = run(SceneKind::stack, Narrowphase::hedra);
  run(SceneKind::stack, Narrowphase::bullet);
  EXPECT_EQ(r.bodies, 10);
  EXPECT_GE(r.hedra_queries, 10L * 60);  // at least the first second, every pair
  EXPECT_LT(r.top_drift, 0.01 * r.size);
  EXPECT_NEAR(r.points_per_manifold, 4.0, 0.05);  // face on face: four corners
  expect_at_rest_and_unbroken(r);
}

TEST(SimulateScenes, FourLevelPyramidStands) {
  const SceneReport r = run(SceneKind::pyramid, Narrowphase::hedra);
  run(SceneKind::pyramid, Narrowphase::bullet);
  EXPECT_EQ(r.bodies, 10);
  EXPECT_GE(r.hedra_queries, 16L * 60);  // 4 on the ground + 12 box-box pairs
  EXPECT_LT(r.top_drift, 0.01 * r.size);
  expect_at_rest_and_unbroken(r);
}

TEST(SimulateScenes, PileOfTwentyHullsSettles) {
  const SceneReport r = run(SceneKind::pile, Narrowphase::hedra);
  run(SceneKind::pile, Narrowphase::bullet);
  EXPECT_EQ(r.bodies, 20);
  EXPECT_GE(r.hedra_queries, 20L * 60);
  EXPECT_GT(r.manifolds_per_step, 15.0);  // a pile, not 20 hulls apart
  expect_at_rest_and_unbroken(r);
  EXPECT_LT(r.max_penetration, 5e-4);
}

}  // namespace
