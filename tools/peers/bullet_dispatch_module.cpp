// Bullet's per-pair narrowphase as its world runs it (bullet_dispatch.h):
// btDefaultCollisionConfiguration's dispatcher picks the algorithm, and
// processCollision fills the pair's persistent manifold. Shapes are built
// as bullet_module.cpp builds them (margins set to hedra's, boxes and
// cylinders at core + margin).
#include <btBulletCollisionCommon.h>
#include <cxxabi.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <typeinfo>

#include "bullet_dispatch.h"

namespace {

std::unique_ptr<btConvexShape> dispatch_shape(const HedraBulletShape& s, bool polyhedral) {
  const auto r = [](double x) { return static_cast<btScalar>(x); };
  std::unique_ptr<btConvexShape> shape;
  switch (s.kind) {
    case hedra_bullet_sphere:
      shape = std::make_unique<btSphereShape>(r(s.radius + s.margin));
      return shape;
    case hedra_bullet_capsule:
      shape = std::make_unique<btCapsuleShapeZ>(r(s.radius + s.margin), r(2.0 * s.half_length));
      return shape;
    case hedra_bullet_box:
      shape = std::make_unique<btBoxShape>(
          btVector3(r(s.half_extents[0] + s.margin), r(s.half_extents[1] + s.margin), r(s.half_extents[2] + s.margin)));
      break;
    case hedra_bullet_cylinder:
      shape = std::make_unique<btCylinderShapeZ>(
          btVector3(r(s.radius + s.margin), r(s.radius + s.margin), r(s.half_length + s.margin)));
      break;
    case hedra_bullet_cone:
      shape = std::make_unique<btConeShapeZ>(r(s.radius), r(2.0 * s.half_length));
      break;
    default: {
      auto hull = std::make_unique<btConvexHullShape>();
      for (size_t i = 0; i < s.point_count; ++i)
        hull->addPoint(btVector3(r(s.points[3 * i]), r(s.points[3 * i + 1]), r(s.points[3 * i + 2])), false);
      hull->recalcLocalAabb();
      shape = std::move(hull);
    }
  }
  shape->setMargin(r(s.margin));
  if (polyhedral && (s.kind == hedra_bullet_box || s.kind == hedra_bullet_hull))
    static_cast<btPolyhedralConvexShape*>(shape.get())->initializePolyhedralFeatures();
  return shape;
}

btTransform dispatch_transform(const double* pose) {
  const auto c = [&](int i) { return static_cast<btScalar>(pose[i]); };
  return btTransform(btMatrix3x3(c(0), c(1), c(2), c(3), c(4), c(5), c(6), c(7), c(8)), btVector3(c(9), c(10), c(11)));
}

struct PreparedDispatch {
  std::unique_ptr<btConvexShape> a, b;
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDispatcherInfo info;
  btCollisionObject object_a, object_b;
  btCollisionAlgorithm* algorithm = nullptr;
  char name[96] = "";

  void drop() {
    if (!algorithm) return;
    algorithm->~btCollisionAlgorithm();
    dispatcher.freeCollisionAlgorithm(algorithm);
    algorithm = nullptr;
  }
  ~PreparedDispatch() { drop(); }
};

}  // namespace

extern "C" {

__attribute__((visibility("default"))) void* hedra_bullet_dispatch_prepare(const HedraBulletShape* a,
                                                                           const HedraBulletShape* b, int polyhedral) {
  auto* p = new PreparedDispatch;
  p->a = dispatch_shape(*a, polyhedral != 0);
  p->b = dispatch_shape(*b, polyhedral != 0);
  p->object_a.setCollisionShape(p->a.get());
  p->object_b.setCollisionShape(p->b.get());
  return p;
}

__attribute__((visibility("default"))) void hedra_bullet_dispatch_query(void* prepared, const double* pose_a,
                                                                        const double* pose_b, int warm,
                                                                        HedraBulletDispatchResult* out) {
  auto& p = *static_cast<PreparedDispatch*>(prepared);
  p.object_a.setWorldTransform(dispatch_transform(pose_a));
  p.object_b.setWorldTransform(dispatch_transform(pose_b));
  const btCollisionObjectWrapper wa(nullptr, p.a.get(), &p.object_a, p.object_a.getWorldTransform(), -1, -1);
  const btCollisionObjectWrapper wb(nullptr, p.b.get(), &p.object_b, p.object_b.getWorldTransform(), -1, -1);
  if (!warm) p.drop();
  if (!p.algorithm) {
    p.algorithm = p.dispatcher.findAlgorithm(&wa, &wb, nullptr, BT_CONTACT_POINT_ALGORITHMS);
    if (!p.name[0] && p.algorithm) {
      int status = 0;
      char* name = abi::__cxa_demangle(typeid(*p.algorithm).name(), nullptr, nullptr, &status);
      std::snprintf(p.name, sizeof(p.name), "%s", status == 0 && name ? name : typeid(*p.algorithm).name());
      std::free(name);
    }
  }
  out->points = 0;
  out->deepest = NAN;
  std::snprintf(out->algorithm, sizeof(out->algorithm), "%s", p.name);
  if (!p.algorithm) return;
  btManifoldResult result(&wa, &wb);
  p.algorithm->processCollision(&wa, &wb, p.info, &result);
  const btPersistentManifold* manifold = result.getPersistentManifold();
  if (!manifold) return;
  out->points = manifold->getNumContacts();
  for (int i = 0; i < out->points; ++i) {
    const double d = static_cast<double>(manifold->getContactPoint(i).getDistance());
    if (!(d >= out->deepest)) out->deepest = d;
  }
}

__attribute__((visibility("default"))) void hedra_bullet_dispatch_release(void* prepared) {
  delete static_cast<PreparedDispatch*>(prepared);
}
}
