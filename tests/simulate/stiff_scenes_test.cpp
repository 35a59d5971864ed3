// The stiff and extreme scenes of scenes.hpp with hedra as the narrowphase
// of Bullet's btDiscreteDynamicsWorld: every body kept awake, 10 s at 60 Hz,
// the start perturbed by 1e-3 (seed 1). Each scene must end with no NaN and
// no body faster than 20 m/s, its deepest interpenetration (the exact
// reference of tools/reference, not hedra) below the scene's bound (a
// fraction of the smaller body's size), and, where the sequential-impulse
// solver can hold it, standing (every body within a quarter of its extent
// of its start, turned by less than 0.2 rad). Not asserted to stand, with
// either narrowphase: the 30-box stack (its sway grows), the 1 kg box under
// 1,000 kg (squeezed out within a second) and the capsule standing on its
// round end (an unstable balance). The plates' bound is the solver's
// resting depth (about 1 mm, 10 % of a 1 cm plate; Bullet's narrowphase:
// 19 %). The rounded 60-hull pile's bound, 0.1 %, is what friction
// anchors held at the old contact's depth broke (0.15 %). One ctest per
// scene; the 60-hull piles are the longest (1 to 3 s each in a release
// build, 13 and 22 s under ASan + UBSan at -O1).
#include <gtest/gtest.h>

#include <cstdio>
#include <ostream>
#include <string>

#include "simulate/scenes.hpp"

namespace {

using namespace hedra::simulate;

struct StiffCase {
  SceneKind scene;
  bool stands;             // asserted to stand
  double max_penetration;  // bound, fraction of the smaller body's size
};

void PrintTo(const StiffCase& c, std::ostream* os) { *os << to_string(c.scene); }

class StiffScenes : public ::testing::TestWithParam<StiffCase> {};

TEST_P(StiffScenes, HedraEndsFiniteUnbrokenAndShallow) {
  const StiffCase& c = GetParam();
  SceneSettings settings;
  settings.scene = c.scene;
  settings.narrowphase = Narrowphase::hedra;
  settings.sleeping = false;
  settings.perturbation = 1e-3;
  const SceneReport r = run_scene(settings);
  std::printf(
      "%s: stands %d, top drift %.3g m, late creep %.3g m, max penetration %.3g%%, jitter %.3g m/s, %.2f "
      "points/manifold\n",
      to_string(c.scene), r.stands, r.top_drift, r.late_creep, 100 * r.max_penetration, r.jitter,
      r.points_per_manifold);
  EXPECT_GE(r.hedra_queries, 60L * r.bodies);  // hedra answered every resting pair
  EXPECT_FALSE(r.non_finite);
  EXPECT_FALSE(r.exploded);
  EXPECT_EQ(r.measure_failures, 0);
  EXPECT_LT(r.max_penetration, c.max_penetration);
  if (c.stands) {
    EXPECT_TRUE(r.stands);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, StiffScenes,
    ::testing::Values(
        StiffCase{SceneKind::stack_20, true, 0.005}, StiffCase{SceneKind::stack_30, false, 0.01},
        StiffCase{SceneKind::mass_100, true, 0.01}, StiffCase{SceneKind::mass_1000, false, 0.01},
        StiffCase{SceneKind::plates, true, 0.15}, StiffCase{SceneKind::plate_1mm, true, 0.01},
        StiffCase{SceneKind::pile_60, false, 0.01}, StiffCase{SceneKind::pile_60_rounded, false, 0.001},
        StiffCase{SceneKind::far_1e4, true, 0.005}, StiffCase{SceneKind::far_1e5, true, 0.005},
        StiffCase{SceneKind::tiny_on_ground, true, 0.01}, StiffCase{SceneKind::tiny_on_box, true, 0.01},
        StiffCase{SceneKind::rounded_boxes, true, 0.005}, StiffCase{SceneKind::rounded_hulls, true, 0.005},
        StiffCase{SceneKind::capsule_lying, true, 0.005}, StiffCase{SceneKind::capsule_standing, false, 0.005},
        StiffCase{SceneKind::cylinder_lying, true, 0.005}, StiffCase{SceneKind::cylinder_standing, true, 0.005},
        StiffCase{SceneKind::cone_standing, true, 0.005}, StiffCase{SceneKind::sphere_on_box, true, 0.005}),
    [](const ::testing::TestParamInfo<StiffCase>& info) {
      std::string name = to_string(info.param.scene);
      for (char& ch : name)
        if (ch == '-') ch = '_';
      return name;
    });

}  // namespace
