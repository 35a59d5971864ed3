// The fast projectile (see the header): one Bullet world per run, hedra's
// continuous collision in the internal tick callbacks.
#include "simulate/projectile.hpp"

#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <hedra/collision/query.hpp>
#include <hedra/collision/time_of_impact.hpp>
#include <memory>
#include <vector>

namespace hedra::simulate {
namespace {

constexpr double kSize = 0.05;  // the sphere's diameter, the cube's edge
constexpr double kPlateHalfThickness = 0.005;
constexpr double kPlateHalfSide = 1.0;

collision::Pose to_pose(const btTransform& t) {
  collision::Pose p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p.rotation(i, j) = t.getBasis()[i][j];
  p.translation = {t.getOrigin().x(), t.getOrigin().y(), t.getOrigin().z()};
  return p;
}

btTransform to_transform(const collision::Pose& p) {
  const auto& r = p.rotation;
  return btTransform(btMatrix3x3(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2)),
                     btVector3(p.translation.x(), p.translation.y(), p.translation.z()));
}

// The exact hedra shape of the two Bullet shapes used here.
collision::Shape hedra_shape(const btCollisionShape* shape) {
  if (shape->getShapeType() == SPHERE_SHAPE_PROXYTYPE)
    return collision::Sphere{static_cast<const btSphereShape*>(shape)->getRadius(), 0.0};
  const btVector3 h = static_cast<const btBoxShape*>(shape)->getHalfExtentsWithMargin();
  return collision::Box{Eigen::Vector3d(h.x(), h.y(), h.z()), 0.0};
}

struct Scene {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
  std::unique_ptr<btCollisionShape> plate_shape, body_shape;
  std::unique_ptr<btRigidBody> plate, body;
  btTransform before;  // the body's pose at the start of the current step
  int clamps = 0;
  ~Scene() {
    world.removeRigidBody(body.get());
    world.removeRigidBody(plate.get());
  }
};

void remember_start(btDynamicsWorld* world, btScalar) {
  auto* scene = static_cast<Scene*>(world->getWorldUserInfo());
  scene->before = scene->body->getWorldTransform();
}

btVector3 to_bullet(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// A perfectly inelastic, sticking impact: the body keeps only its velocity
// along the plate (no approach along `n`, from the body toward the plate,
// and no spin), and Bullet's solver takes the contact from rest. (A
// frictionless impulse at the contact point alone spins a 5 cm cube hit on a
// corner at 200 m/s up to ~5000 rad/s, which then swings its other corners
// through the plate within the next step.)
void stop(btRigidBody& body, const btVector3& n) {
  const btVector3 v = body.getLinearVelocity();
  if (v.dot(n) > 0.0) body.setLinearVelocity(v - v.dot(n) * n);
  body.setAngularVelocity(btVector3(0, 0, 0));
}

// The pose the step may end at: the time of impact of its motion against
// the static plate, where the body stops (stop()). A step that starts
// touching is clamped the same way where the body first gets kSlop deep;
// shallower contact is the solver's.
void clamp_to_time_of_impact(btDynamicsWorld* world, btScalar) {
  constexpr double kSlop = 2e-3 * kSize;
  auto* scene = static_cast<Scene*>(world->getWorldUserInfo());
  btRigidBody& moving = *scene->body;
  const collision::Shape body = hedra_shape(scene->body_shape.get()), plate = hedra_shape(scene->plate_shape.get());
  const collision::Sweep motion{to_pose(scene->before), to_pose(moving.getWorldTransform())};
  const collision::Pose plate_pose = to_pose(scene->plate->getWorldTransform());
  const collision::CastResult r = collision::time_of_impact(body, motion, plate, {plate_pose, plate_pose});
  double fraction = 1.0;
  Eigen::Vector3d normal = r.normal;
  if (r.status == collision::CastStatus::hit) {
    fraction = r.fraction;
  } else if (r.status == collision::CastStatus::initially_overlapping) {
    // Touching at the start: the first time the body reaches kSlop deep,
    // i.e. touches the plate shrunk by kSlop (for a box, exactly its points
    // at least kSlop deep).
    const auto& plate_box = std::get<collision::Box>(plate);
    const collision::Box core{plate_box.half_extents - Eigen::Vector3d::Constant(kSlop), 0.0};
    const collision::CastResult deep = collision::time_of_impact(body, motion, core, {plate_pose, plate_pose});
    if (deep.status != collision::CastStatus::hit) return;
    fraction = deep.fraction;
    normal = deep.normal;
  }
  if (fraction >= 1.0) return;
  const btTransform clamped = to_transform(collision::pose_at(motion, fraction));
  moving.setWorldTransform(clamped);
  moving.setInterpolationWorldTransform(clamped);
  stop(moving, to_bullet(normal));
  ++scene->clamps;
}

}  // namespace

const char* to_string(Projectile projectile) { return projectile == Projectile::sphere ? "sphere" : "box"; }
const char* to_string(Ccd ccd) { return ccd == Ccd::none ? "none" : ccd == Ccd::bullet ? "bullet" : "hedra"; }

ProjectileReport run_projectile(Projectile projectile, Ccd ccd, double seconds, double hz) {
  Scene s;
  s.world.setGravity(btVector3(0, 0, -9.81));
  s.plate_shape = std::make_unique<btBoxShape>(btVector3(kPlateHalfSide, kPlateHalfSide, kPlateHalfThickness));
  s.plate = std::make_unique<btRigidBody>(0.0, nullptr, s.plate_shape.get());
  s.world.addRigidBody(s.plate.get());

  if (projectile == Projectile::sphere)
    s.body_shape = std::make_unique<btSphereShape>(0.5 * kSize);
  else
    s.body_shape = std::make_unique<btBoxShape>(btVector3(0.5 * kSize, 0.5 * kSize, 0.5 * kSize));
  const double mass = 0.1;
  btVector3 inertia(0, 0, 0);
  s.body_shape->calculateLocalInertia(mass, inertia);
  s.body = std::make_unique<btRigidBody>(mass, nullptr, s.body_shape.get(), inertia);
  s.body->setWorldTransform(btTransform(btQuaternion(btVector3(1, 1, 0).normalized(), 0.3), btVector3(0.1, 0, 1.0)));
  s.body->setLinearVelocity(btVector3(1.0, 0.5, -200.0));
  if (projectile == Projectile::box) s.body->setAngularVelocity(btVector3(30.0, 10.0, 0.0));
  s.body->setActivationState(DISABLE_DEACTIVATION);
  if (ccd == Ccd::bullet) {
    s.body->setCcdMotionThreshold(0.5 * kSize);
    s.body->setCcdSweptSphereRadius(0.4 * 0.5 * kSize);
  }
  s.world.addRigidBody(s.body.get());
  if (ccd == Ccd::hedra) {
    s.world.setInternalTickCallback(remember_start, &s, true);
    s.world.setInternalTickCallback(clamp_to_time_of_impact, &s, false);
  }

  ProjectileReport report;
  const collision::Shape body = hedra_shape(s.body_shape.get()), plate = hedra_shape(s.plate_shape.get());
  const int steps = static_cast<int>(seconds * hz + 0.5);
  for (int i = 0; i < steps; ++i) {
    const btVector3 from = s.body->getWorldTransform().getOrigin();
    s.world.stepSimulation(1.0 / hz, 1, 1.0 / hz);
    const btVector3 to = s.body->getWorldTransform().getOrigin();
    // Through the plate: the centre crosses its mid-plane inside its outline
    // (falling past its edge is not tunnelling).
    if (from.z() >= 0.0 && to.z() < 0.0) {
      const btVector3 crossing = from + (to - from) * (from.z() / (from.z() - to.z()));
      if (std::abs(crossing.x()) <= kPlateHalfSide && std::abs(crossing.y()) <= kPlateHalfSide) report.tunnelled = true;
    }
    const collision::PenetrationResult p = collision::penetration(body, to_pose(s.body->getWorldTransform()), plate,
                                                                  to_pose(s.plate->getWorldTransform()));
    if (p.status == collision::Status::ok) report.deepest = std::max(report.deepest, -p.distance);
    ++report.steps;
  }
  report.final_height = s.body->getWorldTransform().getOrigin().z();
  report.clamps = s.clamps;
  return report;
}

}  // namespace hedra::simulate
