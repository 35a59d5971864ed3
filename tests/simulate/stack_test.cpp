// hedra's manifolds driving Bullet's dynamics: a stack of 10 unit boxes on a
// static ground box in btDiscreteDynamicsWorld, with hedra's collision
// algorithm registered for box and hull pairs (Bullet's own solver, hedra's
// points, 50 solver iterations). After 4 s at 60 Hz the stack must still
// stand: no box displaced sideways by more than a tenth of its size (a
// falling stack moves by more than its half size), none sunk or lifted by
// more than 1 cm, none tilted beyond 0.01 rad, all nearly at rest; the same
// with the boxes as convex hulls (the SAT + clipping path on hulls).
// Bullet's own algorithms run the same scene as a baseline, printed for the
// reader, not asserted (the slow sideways creep of a tall stack is the
// solver's, and Bullet's own contacts show it too).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "simulate/hedra_collision_algorithm.hpp"

namespace {

using hedra::simulate::HedraCollisionAlgorithm;

struct StackResult {
  double max_horizontal_drift = 0.0;  // largest |x, y| displacement of a box centre
  double max_height_error = 0.0;      // largest |z - ideal resting height|
  double max_speed = 0.0;             // largest linear speed at the end
  double max_tilt = 0.0;              // largest angle of a box's z axis from vertical (rad)
};

StackResult run_stack(bool use_hedra, bool as_hulls, int boxes = 10, double seconds = 4.0) {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  HedraCollisionAlgorithm::CreateFunc create;
  hedra::simulate::ShapeCache shapes;
  if (use_hedra) hedra::simulate::register_hedra(dispatcher, create, shapes);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0, 0, -9.81));
  world.getSolverInfo().m_numIterations = 50;  // a tall stack needs more than the default 10

  btBoxShape ground_shape(btVector3(20, 20, 0.5));
  btRigidBody ground(0.0, nullptr, &ground_shape);
  ground.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0, -0.5)));
  world.addRigidBody(&ground);

  btBoxShape box_shape(btVector3(0.5, 0.5, 0.5));
  btConvexHullShape hull_shape;
  for (int i = 0; i < 8; ++i)
    hull_shape.addPoint(btVector3(i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5));
  hull_shape.setMargin(0.0);
  btCollisionShape* shape = as_hulls ? static_cast<btCollisionShape*>(&hull_shape) : &box_shape;
  const double half = as_hulls ? 0.5 : box_shape.getHalfExtentsWithMargin().z();
  btVector3 inertia(0, 0, 0);
  shape->calculateLocalInertia(1.0, inertia);
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  std::vector<btVector3> start;
  for (int i = 0; i < boxes; ++i) {
    auto body = std::make_unique<btRigidBody>(1.0, nullptr, shape, inertia);
    const btVector3 at(0, 0, half + 2.0 * half * i);
    body->setWorldTransform(btTransform(btQuaternion::getIdentity(), at));
    body->setActivationState(DISABLE_DEACTIVATION);  // keep the solver working to the end
    world.addRigidBody(body.get());
    start.push_back(at);
    bodies.push_back(std::move(body));
  }
  const int steps = static_cast<int>(seconds * 60.0);
  for (int s = 0; s < steps; ++s) world.stepSimulation(1.0 / 60.0, 1, 1.0 / 60.0);

  StackResult r;
  for (int i = 0; i < boxes; ++i) {
    const btTransform& t = bodies[i]->getWorldTransform();
    const btVector3 d = t.getOrigin() - start[i];
    r.max_horizontal_drift = std::max(r.max_horizontal_drift, std::hypot(d.x(), d.y()));
    r.max_height_error = std::max(r.max_height_error, std::abs(d.z()));
    r.max_speed = std::max(r.max_speed, static_cast<double>(bodies[i]->getLinearVelocity().length()));
    const double up = t.getBasis().getColumn(2).z();
    r.max_tilt = std::max(r.max_tilt, std::acos(std::min(1.0, up)));
  }
  for (auto& body : bodies) world.removeRigidBody(body.get());
  world.removeRigidBody(&ground);
  return r;
}

void print(const char* name, const StackResult& r) {
  std::printf("%s: drift %.3g m, height error %.3g m, speed %.3g m/s, tilt %.3g rad\n", name, r.max_horizontal_drift,
              r.max_height_error, r.max_speed, r.max_tilt);
}

TEST(SimulateStack, TenBoxesStandOnHedraContacts) {
  const long queries = HedraCollisionAlgorithm::queries();
  const StackResult hedra = run_stack(true, false);
  print("hedra boxes", hedra);
  print("bullet boxes (baseline)", run_stack(false, false));
  EXPECT_GT(HedraCollisionAlgorithm::queries(), queries + 10 * 240 - 1);  // every pair, every step
  EXPECT_LT(hedra.max_horizontal_drift, 0.1);
  EXPECT_LT(hedra.max_height_error, 0.01);
  EXPECT_LT(hedra.max_speed, 0.05);
  EXPECT_LT(hedra.max_tilt, 0.01);
}

TEST(SimulateStack, TenHullBoxesStandOnHedraContacts) {
  const long points = HedraCollisionAlgorithm::points();
  const StackResult hedra = run_stack(true, true);
  print("hedra hulls", hedra);
  print("bullet hulls (baseline)", run_stack(false, true));
  EXPECT_GT(HedraCollisionAlgorithm::points(), points + 4 * 10 * 200);  // four points per resting pair
  EXPECT_LT(hedra.max_horizontal_drift, 0.1);
  EXPECT_LT(hedra.max_height_error, 0.01);
  EXPECT_LT(hedra.max_speed, 0.05);
  EXPECT_LT(hedra.max_tilt, 0.01);
}

}  // namespace
