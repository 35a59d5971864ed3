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
//     any contact-breaking threshold (0.02 to 0.05);
//   * a rounded box rolling on its edge under a held friction anchor: Bullet
//     keeps the anchored point, two material points that part along the
//     normal as the edge rolls, and reads the contact shallower than it is
//     (a 20-hull pile sank 0.1 to 0.4 % of its size that way); keep_new makes
//     a held anchor at least as deep as hedra's point;
//   * every point in the manifold reads as Bullet's refresh would measure it
//     (world points and distance from its material points, bit for bit), the
//     points written this frame too: the merge refreshes once a frame;
//   * a unit box 1 cm above a static one gets speculative points only when
//     its speed can close that gap within the step (the contact distance
//     is each body's reach in the step, at most the breaking threshold).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <hedra/collision/query.hpp>
#include <utility>

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

// The manifold points of `dispatcher` whose world points or distance are not
// what Bullet's refresh makes of their material points at the current poses
// (bit for bit), or that the refresh would drop.
int points_unlike_refresh(btCollisionDispatcher& dispatcher) {
  int unlike = 0;
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    btPersistentManifold refreshed = *manifold;
    refreshed.refreshContactPoints(manifold->getBody0()->getWorldTransform(),
                                   manifold->getBody1()->getWorldTransform());
    if (refreshed.getNumContacts() != manifold->getNumContacts()) {
      unlike += manifold->getNumContacts();
      continue;
    }
    for (int k = 0; k < manifold->getNumContacts(); ++k) {
      const btManifoldPoint &p = manifold->getContactPoint(k), &q = refreshed.getContactPoint(k);
      unlike += !(p.m_positionWorldOnA == q.m_positionWorldOnA && p.m_positionWorldOnB == q.m_positionWorldOnB &&
                  p.m_distance1 == q.m_distance1);
    }
  }
  return unlike;
}

// The deepest the cube gets into the plate over 2 s at 60 Hz (exact depth of
// the two sharp boxes Bullet's box shapes are for hedra), the cube with or
// without a friction anchor; `unlike` (if given) adds up the points that do
// not read as Bullet's refresh would measure them, after a narrowphase run
// between the steps (which the next step repeats at the same poses).
double slide(ManifoldUpdate update, double speed, bool anchor = false, int* unlike = nullptr) {
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
  if (anchor) cube.setCollisionFlags(cube.getCollisionFlags() | btCollisionObject::CF_HAS_FRICTION_ANCHOR);
  world.addRigidBody(&cube);
  const collision::Box plate_box{Eigen::Vector3d(1, 1, 0.005)}, cube_box{Eigen::Vector3d::Constant(0.025)};
  double deepest = 0.0;
  for (int step = 0; step < 120; ++step) {
    world.stepSimulation(1.0 / 60, 1, 1.0 / 60);
    const collision::PenetrationResult p = collision::penetration(cube_box, to_pose(cube.getWorldTransform()),
                                                                  plate_box, to_pose(plate.getWorldTransform()));
    deepest = std::max(deepest, -p.distance);
    if (unlike) {  // the next step's narrowphase, at the poses this step ended with, then its points
      world.performDiscreteCollisionDetection();
      *unlike += points_unlike_refresh(dispatcher);
    }
  }
  world.removeRigidBody(&cube);
  world.removeRigidBody(&plate);
  std::printf("%s merge, %.1f m/s%s: deepest %.3e m\n", update == ManifoldUpdate::keep_new ? "keep_new" : "bullet",
              speed, anchor ? ", anchored" : "", deepest);
  return deepest;
}

TEST(ManifoldUpdate, PointByPointMergeLetsASlidingBoxEvictItsOwnPoints) {
  for (const double speed : {0.3, 1.0}) {
    EXPECT_LT(slide(ManifoldUpdate::keep_new, speed), 1e-5) << speed;
    EXPECT_LT(slide(ManifoldUpdate::keep_new, speed, true), 1e-5) << speed;
    EXPECT_GT(slide(ManifoldUpdate::bullet, speed), 1e-3) << speed;  // the failure this guards against
  }
}

TEST(ManifoldUpdate, EveryPointReadsAsBulletsRefreshWouldMeasureIt) {
  for (const double speed : {0.3, 1.0})
    for (const bool anchor : {false, true}) {
      int unlike = 0;
      slide(ManifoldUpdate::keep_new, speed, anchor, &unlike);
      EXPECT_EQ(unlike, 0) << speed << (anchor ? " m/s, anchored" : " m/s");
    }
}

// A btCollisionWorld whose convex pairs go to hedra, and a rounded box: for
// Bullet the hull of its core's corners with the margin, for hedra a Box
// with that margin.
struct HedraWorld {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  HedraCollisionAlgorithm::CreateFunc create;
  simulate::ShapeCache shapes;
  btDbvtBroadphase broadphase;
  btCollisionWorld world{&dispatcher, &broadphase, &configuration};
  btConvexHullShape hull;
  simulate::CachedShape rounded;

  HedraWorld(ManifoldUpdate update, double core, double margin) {
    create.update = update;
    simulate::register_hedra(dispatcher, create, shapes);
    for (int i = 0; i < 8; ++i)
      hull.addPoint(btVector3(i & 1 ? core : -core, i & 2 ? core : -core, i & 4 ? core : -core));
    hull.setMargin(margin);
    rounded.shape = collision::Box{Eigen::Vector3d::Constant(core), margin};
    shapes.set(&hull, rounded);
  }
  // The deepest point of any manifold (-1 if none).
  double deepest() {
    double d = -1.0;
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
      const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
      for (int k = 0; k < manifold->getNumContacts(); ++k)
        d = std::max(d, -static_cast<double>(manifold->getContactPoint(k).getDistance()));
    }
    return d;
  }
};

// Two rounded boxes (core 0.46, margin 0.04) overlapping by 2e-2 through
// the collision algorithm at a given breaking threshold: the deepest point
// Bullet's manifold holds.
double deepest_point(double threshold, double tilt) {
  HedraWorld w(ManifoldUpdate::keep_new, 0.46, 0.04);
  btCollisionObject a, b;
  a.setCollisionShape(&w.hull);
  b.setCollisionShape(&w.hull);
  a.setWorldTransform(btTransform::getIdentity());
  b.setWorldTransform(btTransform(btQuaternion(btVector3(1, 0.3, 0).normalized(), tilt), btVector3(0.3, 0, 0)));
  // Lower b until the exact overlap is 2e-2.
  const collision::Shape& s = w.rounded.shape;
  double lo = 0.5, hi = 1.5;
  for (int i = 0; i < 80; ++i) {
    const double z = 0.5 * (lo + hi);
    b.getWorldTransform().setOrigin(btVector3(0.3, 0, z));
    const double d =
        collision::penetration(s, to_pose(a.getWorldTransform()), s, to_pose(b.getWorldTransform())).distance;
    (d < -0.02 ? lo : hi) = z;
  }
  b.getWorldTransform().setOrigin(btVector3(0.3, 0, hi));
  w.world.addCollisionObject(&a);
  w.world.addCollisionObject(&b);
  w.world.performDiscreteCollisionDetection();
  for (int m = 0; m < w.dispatcher.getNumManifolds(); ++m)
    w.dispatcher.getManifoldByIndexInternal(m)->setContactBreakingThreshold(threshold);
  w.world.performDiscreteCollisionDetection();  // again, at the threshold set
  const double deepest = w.deepest();
  w.world.removeCollisionObject(&b);
  w.world.removeCollisionObject(&a);
  return deepest;
}

// How far a point of a 0.05 rounded edge rises as the edge rolls by `roll`.
double margin_rise(double roll) { return 0.05 * (1.0 - std::cos(roll)); }

// The deepest point of the manifold between a static ground and a rounded
// box (core 0.45, margin 0.05) resting on an edge 1e-3 deep, after the box
// rolls by `roll` rad about that edge (the same depth) with the first
// frame's points held by friction anchors (as a solver leaves them: a
// normal impulse, no friction); and the exact depth.
std::pair<double, double> rolled_edge(ManifoldUpdate update, double roll) {
  const double core = 0.45, margin = 0.05, depth = 1e-3;
  HedraWorld w(update, core, margin);
  btBoxShape ground_shape(btVector3(5, 5, 0.5));
  btCollisionObject ground, box;
  ground.setCollisionShape(&ground_shape);
  ground.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0, -0.5)));
  box.setCollisionShape(&w.hull);
  box.setCollisionFlags(box.getCollisionFlags() | btCollisionObject::CF_HAS_FRICTION_ANCHOR);
  // On the core edge (0, -core, -core), turned 45 degrees about x.
  const double edge_height = core * std::sqrt(2.0);
  box.setWorldTransform(
      btTransform(btQuaternion(btVector3(1, 0, 0), M_PI / 4), btVector3(0, 0, edge_height + margin - depth)));
  w.world.addCollisionObject(&ground);
  w.world.addCollisionObject(&box);
  w.world.performDiscreteCollisionDetection();
  btPersistentManifold* manifold = w.dispatcher.getManifoldByIndexInternal(0);
  for (int k = 0; k < manifold->getNumContacts(); ++k) manifold->getContactPoint(k).m_appliedImpulse = 1.0;
  // Roll about the core edge, the line through (0, 0, margin - depth) along x.
  const btVector3 edge(0, 0, margin - depth);
  const btQuaternion turn(btVector3(1, 0, 0), roll);
  const btTransform& start = box.getWorldTransform();
  box.setWorldTransform(btTransform(turn * start.getRotation(), edge + quatRotate(turn, start.getOrigin() - edge)));
  w.world.performDiscreteCollisionDetection();
  const collision::Box ground_box{Eigen::Vector3d(5, 5, 0.5)};
  const double exact = -collision::penetration(w.rounded.shape, to_pose(box.getWorldTransform()), ground_box,
                                               to_pose(ground.getWorldTransform()))
                            .distance;
  const double deepest = w.deepest();
  w.world.removeCollisionObject(&box);
  w.world.removeCollisionObject(&ground);
  return {deepest, exact};
}

TEST(ManifoldUpdate, FrictionAnchorHoldsTheOldDepthOfARollingBody) {
  for (const double roll : {0.05, 0.1}) {
    const auto [deepest, exact] = rolled_edge(ManifoldUpdate::keep_new, roll);
    EXPECT_NEAR(exact, 1e-3, 1e-9) << roll;
    EXPECT_NEAR(deepest, exact, 1e-9) << roll;
    // The failure this guards against: Bullet's merge keeps the anchored
    // point, which rose by the margin times (1 - cos roll) as the edge rolled.
    const auto [held, exact_too] = rolled_edge(ManifoldUpdate::bullet, roll);
    EXPECT_NEAR(held, exact_too - margin_rise(roll), 1e-6) << roll;
  }
}

TEST(ManifoldUpdate, RoundedBoxesOverlappingByTwoCentimetresKeepThatDepthAtAnyThreshold) {
  for (const double tilt : {0.0, 1e-3, 0.05})
    for (const double threshold : {0.02, 0.021, 0.03, 0.05}) {
      const double deepest = deepest_point(threshold, tilt);
      EXPECT_NEAR(deepest, 0.02, 1e-9) << "threshold " << threshold << ", tilt " << tilt;
    }
}

// The points in the manifold between a static unit box and a unit box 1 cm
// above it moving down at `speed` (no gravity), after one 60 Hz step.
int points_one_centimetre_apart(double speed) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  HedraCollisionAlgorithm::CreateFunc create;
  simulate::ShapeCache shapes;
  simulate::register_hedra(dispatcher, create, shapes);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, 0, 0));
  btBoxShape shape(btVector3(0.5, 0.5, 0.5));
  btRigidBody ground(0.0, nullptr, &shape);
  world.addRigidBody(&ground);
  btVector3 inertia;
  shape.calculateLocalInertia(1.0, inertia);
  btRigidBody box(1.0, nullptr, &shape, inertia);
  box.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0.1, 0, 1.01)));
  box.setLinearVelocity(btVector3(0, 0, -speed));
  world.addRigidBody(&box);
  world.stepSimulation(1.0 / 60, 1, 1.0 / 60);
  int points = 0;
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    EXPECT_GT(manifold->getContactBreakingThreshold(), 0.01);  // the gap is within Bullet's threshold
    points += manifold->getNumContacts();
  }
  world.removeRigidBody(&box);
  world.removeRigidBody(&ground);
  return points;
}

TEST(ManifoldUpdate, SpeculativePointsOnlyWhereTheStepCanCloseTheGap) {
  EXPECT_EQ(points_one_centimetre_apart(0.0), 0);
  EXPECT_EQ(points_one_centimetre_apart(0.3), 0);  // 5 mm in the step
  EXPECT_EQ(points_one_centimetre_apart(1.0), 4);  // 16.7 mm: the face's four corners
}

}  // namespace
