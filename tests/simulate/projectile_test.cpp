// Continuous collision inside Bullet's world (tools/simulate/projectile.hpp):
// a 5 cm sphere and a 5 cm spinning cube at 200 m/s onto a 1 cm plate, 3.3 m
// a step at 60 Hz. Without continuous collision both pass through (the scene
// is hard); with hedra's time_of_impact clamping each step's motion neither
// does, and neither sinks into the plate deeper than 1% of its size.
// Bullet's own CCD runs beside it, printed, not asserted.
#include "simulate/projectile.hpp"

#include <gtest/gtest.h>

#include <cstdio>

namespace {

using namespace hedra::simulate;

ProjectileReport run(Projectile body, Ccd ccd) {
  const ProjectileReport r = run_projectile(body, ccd);
  std::printf("%s, ccd %s: tunnelled %s, final height %.4f m, deepest %.2e m, clamps %d\n", to_string(body),
              to_string(ccd), r.tunnelled ? "yes" : "no", r.final_height, r.deepest, r.clamps);
  return r;
}

TEST(Projectile, WithoutContinuousCollisionBothPassThrough) {
  EXPECT_TRUE(run(Projectile::sphere, Ccd::none).tunnelled);
  EXPECT_TRUE(run(Projectile::box, Ccd::none).tunnelled);
}

TEST(Projectile, HedrasTimeOfImpactNeverTunnels) {
  for (const Projectile body : {Projectile::sphere, Projectile::box}) {
    const ProjectileReport r = run(body, Ccd::hedra);
    EXPECT_FALSE(r.tunnelled) << to_string(body);
    EXPECT_GT(r.final_height, 0.005) << to_string(body);  // on or above the plate's top
    EXPECT_LE(r.deepest, 0.01 * 0.05) << to_string(body);
    EXPECT_GE(r.clamps, 1) << to_string(body);
  }
}

TEST(Projectile, BulletsOwnCcdBeside) {
  for (const Projectile body : {Projectile::sphere, Projectile::box}) run(body, Ccd::bullet);
}

}  // namespace
