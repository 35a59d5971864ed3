// How hedra's manifold goes into Bullet's btPersistentManifold
// (hedra_collision_algorithm.hpp, ManifoldUpdate), checked on the scenes
// that showed why it matters:
//   * a 5 cm cube sliding (0.3 and 1 m/s) to rest on a static 1 cm plate:
//     with Bullet's point-by-point merge (btManifoldResult::addContactPoint)
//     the cube's points, added into a full manifold whose body 0 is the
//     plate, match no old point (they slid beyond the 0.87 mm breaking
//     threshold), evict one another by Bullet's area rule, and the refresh
//     drops the stale ones: the solver gets 1 to 3 of hedra's 4 points and
//     the cube rocks onto its leading edge, several millimetres deep. Merged
//     as a whole frame (keep_new) it stays within 1e-5 m of the surface;
//   * two rounded boxes overlapping by 2e-2 keep a point of that depth at
//     any contact-breaking threshold (0.02 to 0.05).
#include <gtest/gtest.h>

#include <cstdio>
#include <hedra/collision/query.hpp>

#include "simulate/hedra_collision_algorithm.hpp"

namespace {

using namespace hedra;
using simulate::HedraCollisionAlgorithm;
using simulate::ManifoldUpdate;

collision::Pose to_pose(const btTransform& t) {
  collision::Pose p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p.rotation(i, j) = t.getBasis()[i][j];
  p.translation = {t.getOrigin().x(), t.getOrigin().y(), t.getOrigin().z()};
  return p;
}

// The deepest the cube gets into the plate over 2 s at 60 Hz (exact depth of
// the two sharp boxes Bullet's box shapes are for hedra).
double slide(ManifoldUpdate update, double speed) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  HedraCollisionAlgorithm::CreateFunc create;
  create.update = update;
  simulate::ShapeCache shapes;
  simulate::register_hedra(dispatcher, create, shapes);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, 0, -9.81));
  btBoxShape plate_shape(btVector3(1, 1, 0.005));
  btRigidBody plate(0.0, nullptr, &plate_shape);
  world.addRigidBody(&plate);  // first: body 0 of the pair's manifold
  btBoxShape cube_shape(btVector3(0.025, 0.025, 0.025));
  btVector3 inertia;
  cube_shape.calculateLocalInertia(0.1, inertia);
  btRigidBody cube(0.1, nullptr, &cube_shape, inertia);
  cube.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(-0.5, 0, 0.03)));
  cube.setLinearVelocity(btVector3(speed, 0.3 * speed, 0));
  cube.setActivationState(DISABLE_DEACTIVATION);
  world.addRigidBody(&cube);
  const collision::Box plate_box{Eigen::Vector3d(1, 1, 0.005)}, cube_box{Eigen::Vector3d::Constant(0.025)};
  double deepest = 0.0;
  for (int step = 0; step < 120; ++step) {
    world.stepSimulation(1.0 / 60, 1, 1.0 / 60);
    const collision::PenetrationResult p = collision::penetration(cube_box, to_pose(cube.getWorldTransform()),
                                                                  plate_box, to_pose(plate.getWorldTransform()));
    deepest = std::max(deepest, -p.distance);
  }
  world.removeRigidBody(&cube);
  world.removeRigidBody(&plate);
  std::printf("%s merge, %.1f m/s: deepest %.3e m\n", update == ManifoldUpdate::keep_new ? "keep_new" : "bullet", speed,
              deepest);
  return deepest;
}

TEST(ManifoldUpdate, PointByPointMergeLetsASlidingBoxEvictItsOwnPoints) {
  for (const double speed : {0.3, 1.0}) {
    EXPECT_LT(slide(ManifoldUpdate::keep_new, speed), 1e-5) << speed;
    EXPECT_GT(slide(ManifoldUpdate::bullet, speed), 1e-3) << speed;  // the failure this guards against
  }
}

// Two rounded boxes (core 0.46, margin 0.04) overlapping by 2e-2 through
// the collision algorithm at a given breaking threshold: the deepest point
// Bullet's manifold holds.
double deepest_point(double threshold, double tilt) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  HedraCollisionAlgorithm::CreateFunc create;
  simulate::ShapeCache shapes;
  simulate::register_hedra(dispatcher, create, shapes);
  btDbvtBroadphase broadphase;
  btCollisionWorld world(&dispatcher, &broadphase, &configuration);
  btConvexHullShape hull;
  for (int i = 0; i < 8; ++i)
    hull.addPoint(btVector3(i & 1 ? 0.46 : -0.46, i & 2 ? 0.46 : -0.46, i & 4 ? 0.46 : -0.46));
  hull.setMargin(0.04);
  simulate::CachedShape rounded;
  rounded.shape = collision::Box{Eigen::Vector3d::Constant(0.46), 0.04};
  shapes.set(&hull, rounded);
  btCollisionObject a, b;
  a.setCollisionShape(&hull);
  b.setCollisionShape(&hull);
  a.setWorldTransform(btTransform::getIdentity());
  b.setWorldTransform(btTransform(btQuaternion(btVector3(1, 0.3, 0).normalized(), tilt), btVector3(0.3, 0, 0)));
  // Lower b until the exact overlap is 2e-2.
  const collision::Shape& s = rounded.shape;
  double lo = 0.5, hi = 1.5;
  for (int i = 0; i < 80; ++i) {
    const double z = 0.5 * (lo + hi);
    b.getWorldTransform().setOrigin(btVector3(0.3, 0, z));
    const double d =
        collision::penetration(s, to_pose(a.getWorldTransform()), s, to_pose(b.getWorldTransform())).distance;
    (d < -0.02 ? lo : hi) = z;
  }
  b.getWorldTransform().setOrigin(btVector3(0.3, 0, hi));
  world.addCollisionObject(&a);
  world.addCollisionObject(&b);
  world.performDiscreteCollisionDetection();
  double deepest = -1.0;
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    manifold->setContactBreakingThreshold(threshold);
  }
  world.performDiscreteCollisionDetection();  // again, at the threshold set
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    for (int k = 0; k < manifold->getNumContacts(); ++k)
      deepest = std::max(deepest, -static_cast<double>(manifold->getContactPoint(k).getDistance()));
  }
  world.removeCollisionObject(&b);
  world.removeCollisionObject(&a);
  return deepest;
}

TEST(ManifoldUpdate, RoundedBoxesOverlappingByTwoCentimetresKeepThatDepthAtAnyThreshold) {
  for (const double tilt : {0.0, 1e-3, 0.05})
    for (const double threshold : {0.02, 0.021, 0.03, 0.05}) {
      const double deepest = deepest_point(threshold, tilt);
      EXPECT_NEAR(deepest, 0.02, 1e-9) << "threshold " << threshold << ", tilt " << tilt;
    }
}

}  // namespace
