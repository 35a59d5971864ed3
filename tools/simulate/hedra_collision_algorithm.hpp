// hedra's contact manifolds inside Bullet's dynamics: a btCollisionAlgorithm
// for Bullet's convex primitives (box, hull, sphere, capsule, cylinder, cone)
// that runs hedra::collision::contact() and merges its points into the
// pair's btPersistentManifold, so that Bullet's own solver
// (btSequentialImpulseConstraintSolver) stacks bodies on hedra's points.
// Built against Bullet's double-precision libraries (BT_USE_DOUBLE_PRECISION),
// like hedra.
//
// Conventions converted: Bullet wants the normal on B (from B toward A), the
// point on B and a signed distance (< 0 penetration); hedra gives the normal
// from A toward B, the midpoint and the depth (> 0 penetration). Shapes, the
// solid Bullet's GJK sees (core + margin), but for boxes:
//   btBoxShape        a sharp Box of its outer half extents (as Bullet's own
//                     box-box detector uses them; its GJK rounds the corners);
//   btConvexHullShape a ConvexPolyhedron of its scaled points, rounded by the
//                     margin (built once per Bullet shape and cached);
//   btSphereShape     Sphere{radius};  btCapsuleShapeZ  Capsule{radius, half height};
//   btCylinderShapeZ  Cylinder of the half extents without margin, rounded by it;
//   btConeShapeZ      Cone{radius, height / 2}, rounded by the margin.
// Margins mean the opposite: hedra's grows the shape (Box{h, m} reaches
// h + m), Bullet's box and cylinder margins lie inside their extents
// (btBoxShape(h) reaches h, its core h - m), so a Bullet box of margin m is
// Box{h - m, m} rounded or Box{h} sharp, never Box{h, m} (m too large);
// Bullet's hull margin grows the hull, as hedra's does (docs/embedding.md).
// ShapeCache::set() gives a Bullet shape another hedra shape (a rounded Box
// for the hull of its corners). hedra keeps a hull's vertices relative to its
// centroid (ConvexPolyhedron::offset()), so the hull is posed at the body's
// transform applied to that offset. The speculative contact distance is how
// far the two bodies can close within the step, at most the manifold's
// contact-breaking threshold: each body's speed bound |v| + |w| r (r: the
// radius of its shape around its origin; v with the velocity this step's
// external forces add) times the step, summed. A point farther apart than
// that cannot be closed at the velocities the solver starts from, so Bullet's
// solver gives it no impulse (a speculative row acts only when the approach
// closes its gap; should the solver speed the bodies up, the next step
// reports the point) and would only pay for its rows: a stack of 1 cm
// plates, 1 cm from the plate above their neighbour, had four such points a
// pair. Each pair keeps its ContactCache.
// Each frame hedra's points are merged into the manifold (ManifoldUpdate),
// deepest first, then around the contact polygon (the order Bullet's solver
// visits them; see polygon_order()). The keep_new merge writes Bullet's
// points itself: it sets the combined friction, restitution, rolling and
// spinning friction and the friction anchor, not contact stiffness or
// damping, and calls no gContactAddedCallback. It refreshes the manifold
// once a frame, before the merge (gContactProcessedCallback sees the points
// carried over, not the new ones), and writes each point as that refresh
// would measure it.
#pragma once

#include <BulletCollision/CollisionDispatch/btActivatingCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <LinearMath/btPoolAllocator.h>
#include <btBulletDynamicsCommon.h>

#include <hedra/collision/manifold.hpp>
#include <map>
#include <memory>
#include <mutex>

namespace hedra::simulate {

// A hedra shape for a Bullet shape: `shape` sits at `offset` in the Bullet
// shape's frame (a hull's centroid; zero for a box).
struct CachedShape {
  collision::Shape shape;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  // The hedra pose of the shape for a Bullet world transform.
  collision::Pose pose(const btTransform& world) const;
};

// hedra shapes for Bullet shapes, built once per Bullet shape.
class ShapeCache {
 public:
  // Null for other shapes (and hulls quickhull rejects). The pointer stays
  // valid as long as the cache.
  const CachedShape* get(const btCollisionShape* shape);
  // `shape` answers for the Bullet shape from now on (call it before the
  // world steps: get() pointers handed out earlier keep the old shape).
  void set(const btCollisionShape* bullet, const CachedShape& shape);

 private:
  std::mutex mutex_;
  std::map<const btCollisionShape*, std::unique_ptr<CachedShape>> shapes_;
};

// How hedra's points go into the pair's btPersistentManifold each frame.
enum class ManifoldUpdate {
  // Bullet's merge made for a whole manifold a frame (merge_points() in the
  // source): stale old points dropped first, a new point continuing the old
  // one Bullet matches (warm start, friction anchor; a held anchor never
  // reads shallower than hedra's point), and no new point evicting another
  // of the same frame.
  keep_new,
  // Bullet's own merge (btManifoldResult::addContactPoint), made for
  // detectors that add one point a frame: in a full manifold a new point
  // can evict one added just before, and a sliding body loses points.
  bullet,
};

class HedraCollisionAlgorithm : public btActivatingCollisionAlgorithm {
 public:
  HedraCollisionAlgorithm(const btCollisionAlgorithmConstructionInfo& ci, const btCollisionObjectWrapper* a,
                          const btCollisionObjectWrapper* b, ShapeCache* shapes,
                          ManifoldUpdate update = ManifoldUpdate::keep_new);
  ~HedraCollisionAlgorithm() override;

  void processCollision(const btCollisionObjectWrapper* a, const btCollisionObjectWrapper* b,
                        const btDispatcherInfo& info, btManifoldResult* result) override;
  btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                 btManifoldResult*) override {
    return btScalar(1);
  }
  void getAllContactManifolds(btManifoldArray& manifolds) override {
    if (manifold_ && own_manifold_) manifolds.push_back(manifold_);
  }

  struct CreateFunc : public btCollisionAlgorithmCreateFunc {
    ShapeCache* shapes = nullptr;
    ManifoldUpdate update = ManifoldUpdate::keep_new;
    btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& ci,
                                                   const btCollisionObjectWrapper* a,
                                                   const btCollisionObjectWrapper* b) override {
      // Bullet's pool hands out elements of its largest built-in algorithm's
      // size and ignores the size asked for in release builds: beyond it,
      // allocate beside the pool (the dispatcher frees either kind).
      auto* dispatcher = static_cast<btCollisionDispatcher*>(ci.m_dispatcher1);
      const int pool = dispatcher->getCollisionConfiguration()->getCollisionAlgorithmPool()->getElementSize();
      void* memory = sizeof(HedraCollisionAlgorithm) <= static_cast<std::size_t>(pool)
                         ? dispatcher->allocateCollisionAlgorithm(sizeof(HedraCollisionAlgorithm))
                         : btAlignedAlloc(sizeof(HedraCollisionAlgorithm), 16);
      return new (memory) HedraCollisionAlgorithm(ci, a, b, shapes, update);
    }
  };

  // Queries answered and contact points written, over all pairs (tests).
  static long queries();
  static long points();

 private:
  btPersistentManifold* manifold_ = nullptr;
  bool own_manifold_ = false;
  ShapeCache* shapes_;
  const btCollisionShape* bullet_a_ = nullptr;
  const btCollisionShape* bullet_b_ = nullptr;
  const CachedShape* shape_a_ = nullptr;
  const CachedShape* shape_b_ = nullptr;
  double radius_a_ = 0.0;  // of a ball around each body's origin holding its shape
  double radius_b_ = 0.0;
  ManifoldUpdate update_;
  collision::ContactCache cache_;

  // The contact distance of this frame: how far the two bodies can close
  // within the step (see the file's note), at most the manifold's
  // contact-breaking threshold.
  double speculative_distance(const btCollisionObject* a, const btCollisionObject* b,
                              const btDispatcherInfo& info) const;
};

// Registers hedra for every pair of the shapes above in `dispatcher`. `create` and `shapes` must outlive the
// dispatcher.
void register_hedra(btCollisionDispatcher& dispatcher, HedraCollisionAlgorithm::CreateFunc& create, ShapeCache& shapes);

}  // namespace hedra::simulate
