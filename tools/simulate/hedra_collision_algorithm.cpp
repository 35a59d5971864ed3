// hedra's contact manifolds as a Bullet collision algorithm (see the header).
#include "simulate/hedra_collision_algorithm.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

namespace hedra::simulate {
namespace {

std::atomic<long> g_queries{0};
std::atomic<long> g_points{0};

Eigen::Vector3d to_eigen(const btVector3& v) { return {v.x(), v.y(), v.z()}; }
btVector3 to_bullet(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

collision::Pose to_pose(const btTransform& t) {
  collision::Pose p;
  const btMatrix3x3& b = t.getBasis();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) p.rotation(i, j) = b[i][j];
  p.translation = to_eigen(t.getOrigin());
  return p;
}

// The order in which `r`'s points go into Bullet's manifold: the deepest
// (hedra's first) and then counter-clockwise around the normal, i.e. around
// the contact polygon. Bullet's sequential-impulse solver visits a
// manifold's points in this order; hedra's reduction order (deepest,
// farthest from it, then the two largest triangles) puts two diagonal
// corners first, which loads a resting box on one diagonal and, measured
// over 8 perturbed 10-box stacks, doubled the stack's sideways drift
// (0.7% of the box size against 0.35% in polygon order).
void polygon_order(const collision::ContactResult& r, int (&order)[collision::kMaxContactPoints]) {
  for (int k = 0; k < collision::kMaxContactPoints; ++k) order[k] = k;
  if (r.count < 3) return;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int k = 0; k < r.count; ++k) centre += r.points[k].point;
  centre /= r.count;
  const Eigen::Vector3d u = r.points[0].point - centre;
  const Eigen::Vector3d v = r.normal.cross(u);
  // A pseudo-angle in [0, 4) that grows with the angle from u around the
  // normal (the same order as atan2's, without its cost).
  double angle[collision::kMaxContactPoints] = {};
  for (int k = 1; k < r.count; ++k) {
    const Eigen::Vector3d d = r.points[k].point - centre;
    const double x = d.dot(u), y = d.dot(v);
    const double sum = std::abs(x) + std::abs(y);
    const double t = sum > 0.0 ? y / sum : 0.0;  // in [-1, 1]
    angle[k] = x >= 0.0 ? (t >= 0.0 ? t : 4.0 + t) : 2.0 - t;
  }
  for (int k = 2; k < r.count; ++k)  // insertion sort of order[1, count) by angle
    for (int j = k; j > 1 && angle[order[j]] < angle[order[j - 1]]; --j) std::swap(order[j], order[j - 1]);
}

// Whether Bullet's points of the pair are friction anchors (either body
// asks for them).
int anchor_flag(const btCollisionObject* body0, const btCollisionObject* body1) {
  const bool anchors =
      (body0->getCollisionFlags() | body1->getCollisionFlags()) & btCollisionObject::CF_HAS_FRICTION_ANCHOR;
  return anchors ? BT_CONTACT_FLAG_FRICTION_ANCHOR : 0;
}

// What the points Bullet writes for a pair share: the combined material, as
// btManifoldResult::addContactPoint makes it, and the friction anchor flag.
struct PairMaterial {
  double friction, restitution, rolling_friction, spinning_friction;
  int flags;
  PairMaterial(const btCollisionObject* body0, const btCollisionObject* body1)
      : friction(btManifoldResult::calculateCombinedFriction(body0, body1)),
        restitution(btManifoldResult::calculateCombinedRestitution(body0, body1)),
        rolling_friction(btManifoldResult::calculateCombinedRollingFriction(body0, body1)),
        spinning_friction(btManifoldResult::calculateCombinedSpinningFriction(body0, body1)),
        flags(anchor_flag(body0, body1)) {}
};

// How Bullet holds a contact point: by its two material points (each in its
// body's frame) and its world normal; its two world points and its distance
// are what the material points read at the current poses
// (btPersistentManifold::refreshContactPoints writes them so). measure()
// writes them so for a point written or moved this frame, the same
// arithmetic as Bullet's refresh, so the solver reads a new point exactly as
// it would read it after one.
void measure(btManifoldPoint& p, const btTransform& body0, const btTransform& body1) {
  p.m_positionWorldOnA = body0(p.m_localPointA);
  p.m_positionWorldOnB = body1(p.m_localPointB);
  p.m_distance1 = (p.m_positionWorldOnA - p.m_positionWorldOnB).dot(p.m_normalWorldOnB);
}

// hedra's point `p` (normal `n` from A toward B) in the manifold's body
// order (its body 0 is A unless `swapped`): the two surface points, the
// normal on body 1 (from body 1 toward body 0), the signed distance (< 0
// penetration), and the point on body 0 in its own frame, which is how
// Bullet matches a new point to an old one.
struct NewPoint {
  btVector3 world0, world1, normal, local0;
  double distance;
  NewPoint(const collision::ContactPoint& p, const Eigen::Vector3d& n, const btTransform& body0, bool swapped)
      : distance(-p.depth) {
    const btVector3 on_a = to_bullet(p.point + 0.5 * p.depth * n), on_b = to_bullet(p.point - 0.5 * p.depth * n);
    world0 = swapped ? on_b : on_a;
    world1 = swapped ? on_a : on_b;
    normal = to_bullet(swapped ? n : Eigen::Vector3d(-n));
    local0 = body0.invXform(world0);
  }
  // The whole Bullet point, with the pair's material, measured (measure()).
  btManifoldPoint written(const btTransform& body0, const btTransform& body1, const PairMaterial& material) const {
    btManifoldPoint q(local0, body1.invXform(world1), normal, distance);
    measure(q, body0, body1);
    q.m_combinedFriction = material.friction;
    q.m_combinedRestitution = material.restitution;
    q.m_combinedRollingFriction = material.rolling_friction;
    q.m_combinedSpinningFriction = material.spinning_friction;
    q.m_contactPointFlags |= material.flags;
    return q;
  }
};

// The manifold's point that `q` continues, as Bullet's getCacheEntry finds
// it (the nearest within the breaking threshold `threshold` in body 0's
// frame), among the points not written this frame; -1 if none.
int continued(const btPersistentManifold& manifold, const NewPoint& q, double threshold,
              const bool (&fresh)[MANIFOLD_CACHE_SIZE]) {
  int match = -1;
  double nearest = threshold * threshold;
  for (int k = 0; k < manifold.getNumContacts(); ++k) {
    const double d2 = (manifold.getContactPoint(k).m_localPointA - q.local0).length2();
    if (!fresh[k] && d2 < nearest) {
      nearest = d2;
      match = k;
    }
  }
  return match;
}

// Bullet's friction anchor (btPersistentManifold::replaceContactPoint with
// BT_CONTACT_FLAG_FRICTION_ANCHOR): the old point `old` is kept instead of
// the new point that continues it while its friction impulse stays inside
// the Coulomb cone.
bool anchor_holds(const btManifoldPoint& old, int anchor) {
  if (!(anchor & BT_CONTACT_FLAG_FRICTION_ANCHOR)) return false;
  const double lateral = old.m_appliedImpulseLateral1 * old.m_appliedImpulseLateral1 +
                         old.m_appliedImpulseLateral2 * old.m_appliedImpulseLateral2;
  const double cone = old.m_combinedFriction * old.m_appliedImpulse;
  return lateral <= cone * cone;
}

// A held anchor `p` keeps its two material points and its world normal, so
// the depth the solver reads from it is the old contact's: on a body that
// rolls (a rounded corner or edge, a hull tipping over an edge) the two
// material points part along the normal while the surfaces overlap as deep
// as before, and the solver lets the body sink (a 20-hull pile, 0.1 to
// 0.4 % of its size). Here the point on body 0 moves along the held normal
// until the point reads the new point's `distance`, if it read shallower.
// `p` was refreshed this frame (its world points and distance are those of
// its material points at the current poses). The held normal stays (it is
// fixed in the world: given the new one, which tilts with the bodies, the
// 2 cm boxes on a unit box fell in 8 of 9 runs), and a point reading deeper
// stays (raised too, one pile run in 40 ended 0.1 % deep). The sideways
// offset of the two material points, which the refresh checks against the
// breaking threshold, is unchanged.
void deepen_held_anchor(btManifoldPoint& p, double distance, const btTransform& body0, const btTransform& body1) {
  if (p.m_distance1 <= distance) return;
  const btVector3 moved = p.m_positionWorldOnA + p.m_normalWorldOnB * (distance - p.m_distance1);
  p.m_localPointA = body0.invXform(moved);
  measure(p, body0, body1);
}

// Twice the largest area of a quadrilateral through four points, over the
// three ways of pairing them as diagonals.
double quad_area(const btVector3 (&p)[MANIFOLD_CACHE_SIZE]) {
  const double a = (p[0] - p[1]).cross(p[2] - p[3]).length2();
  const double b = (p[0] - p[2]).cross(p[1] - p[3]).length2();
  const double c = (p[0] - p[3]).cross(p[1] - p[2]).length2();
  return std::max({a, b, c});
}

// The old point `q` replaces in a full manifold: among those not written
// this frame, the one whose replacement leaves the widest quadrilateral (the
// area rule of Bullet's btPersistentManifold::sortCachedPoints, which keeps
// the support of a resting body wide).
int stale(const btPersistentManifold& manifold, const NewPoint& q, const bool (&fresh)[MANIFOLD_CACHE_SIZE]) {
  int out = -1;
  double widest = -1.0;
  for (int k = 0; k < MANIFOLD_CACHE_SIZE; ++k) {
    if (fresh[k]) continue;
    btVector3 p[MANIFOLD_CACHE_SIZE];
    for (int j = 0; j < MANIFOLD_CACHE_SIZE; ++j) p[j] = j == k ? q.local0 : manifold.getContactPoint(j).m_localPointA;
    const double area = quad_area(p);
    if (area > widest) {
      widest = area;
      out = k;
    }
  }
  return out;
}

// Bullet's merge of a frame's points into the persistent manifold, made for
// a full manifold, in three steps:
//   1. refresh: the old points are re-measured at the current poses (their
//      material points) and those that no longer hold go (Bullet's
//      refreshContactPoints: apart beyond the breaking threshold, or slid
//      sideways past it). It is the frame's only refresh: the points written
//      below are measured as it would measure them (measure()).
//   2. match: each new point continues the old one Bullet would match
//      (continued()); a held friction anchor stays, made at least as deep as
//      the new point (deepen_held_anchor()), else the new point replaces it
//      keeping its warm start (btPersistentManifold::replaceContactPoint).
//   3. add: an unmatched new point takes a free slot, or in a full manifold
//      the old point whose replacement leaves the widest quadrilateral
//      (stale()); it never evicts another of the same frame (Bullet's area
//      rule, made for one new point a frame, may).
// A held anchor needs only the new point's distance: the whole Bullet point,
// and the pair's combined material, are made only where a point is written
// (a resting pair's anchors mostly hold).
void merge_points(const collision::ContactResult& r, const int (&order)[collision::kMaxContactPoints],
                  const btCollisionObject* a, btPersistentManifold& manifold) {
  const btCollisionObject* object0 = manifold.getBody0();
  const btCollisionObject* object1 = manifold.getBody1();
  const btTransform& body0 = object0->getWorldTransform();
  const btTransform& body1 = object1->getWorldTransform();
  manifold.refreshContactPoints(body0, body1);
  if (r.count == 0) return;
  const double threshold = manifold.getContactBreakingThreshold();
  const int anchor = anchor_flag(object0, object1);
  std::optional<PairMaterial> material;
  const auto written = [&](const NewPoint& q) {
    if (!material) material.emplace(object0, object1);
    return q.written(body0, body1, *material);
  };
  bool fresh[MANIFOLD_CACHE_SIZE] = {};
  for (int i = 0; i < r.count && i < MANIFOLD_CACHE_SIZE; ++i) {
    const NewPoint q(r.points[order[i]], r.normal, body0, object0 != a);
    int slot = continued(manifold, q, threshold, fresh);
    if (slot >= 0 && anchor_holds(manifold.getContactPoint(slot), anchor)) {
      deepen_held_anchor(manifold.getContactPoint(slot), q.distance, body0, body1);
    } else if (slot >= 0) {
      manifold.replaceContactPoint(written(q), slot);
    } else if (manifold.getNumContacts() < MANIFOLD_CACHE_SIZE) {
      slot = manifold.addManifoldPoint(written(q), true);
    } else {
      slot = stale(manifold, q, fresh);  // some point is old: at most 3 of 4 written yet
      btAssert(slot >= 0);
      manifold.getContactPoint(slot) = written(q);
    }
    fresh[slot] = true;
  }
}

// The hedra shape of a Bullet convex primitive; false for other shapes.
bool primitive_shape(const btCollisionShape* shape, collision::Shape& out) {
  switch (shape->getShapeType()) {
    case BOX_SHAPE_PROXYTYPE:
      out = collision::Box{to_eigen(static_cast<const btBoxShape*>(shape)->getHalfExtentsWithMargin())};
      return true;
    case SPHERE_SHAPE_PROXYTYPE:
      out = collision::Sphere{static_cast<const btSphereShape*>(shape)->getRadius()};
      return true;
    case CAPSULE_SHAPE_PROXYTYPE: {
      const auto* capsule = static_cast<const btCapsuleShape*>(shape);
      if (capsule->getUpAxis() != 2) return false;
      out = collision::Capsule{capsule->getRadius(), capsule->getHalfHeight()};
      return true;
    }
    case CYLINDER_SHAPE_PROXYTYPE: {
      const auto* cylinder = static_cast<const btCylinderShape*>(shape);
      if (cylinder->getUpAxis() != 2) return false;
      const btVector3 core = cylinder->getHalfExtentsWithoutMargin();
      out = collision::Cylinder{core.x(), core.z(), cylinder->getMargin()};
      return true;
    }
    case CONE_SHAPE_PROXYTYPE: {
      const auto* cone = static_cast<const btConeShape*>(shape);
      if (cone->getConeUpIndex() != 2) return false;
      out = collision::Cone{cone->getRadius(), 0.5 * cone->getHeight(), cone->getMargin()};
      return true;
    }
    default:
      return false;
  }
}

// How far any point of `object` (within `radius` of its origin) can move in
// `dt`: its speed bound |v| + |w| radius, with the velocity this step's
// external forces (gravity) add before the solver runs; 0 for a static body.
double reach(const btCollisionObject* object, double radius, double dt) {
  const btRigidBody* body = btRigidBody::upcast(object);
  if (!body) return 0.0;
  const btVector3 v = body->getLinearVelocity() + body->getTotalForce() * (body->getInvMass() * dt);
  return dt * (v.length() + body->getAngularVelocity().length() * radius);
}

// The radius of a ball around the body's origin that holds the shape.
double origin_radius(const btCollisionShape* shape) {
  btVector3 centre;
  btScalar radius;
  shape->getBoundingSphere(centre, radius);
  return centre.length() + radius;
}

}  // namespace

collision::Pose CachedShape::pose(const btTransform& world) const {
  collision::Pose p = to_pose(world);
  if (offset != Eigen::Vector3d::Zero()) p.translation = p.apply(offset);  // a hull's centroid; zero for the primitives
  return p;
}

const CachedShape* ShapeCache::get(const btCollisionShape* shape) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto found = shapes_.find(shape);
  if (found != shapes_.end()) return found->second.get();
  auto made = std::make_unique<CachedShape>();
  if (shape->getShapeType() == CONVEX_HULL_SHAPE_PROXYTYPE) {
    const auto* hull = static_cast<const btConvexHullShape*>(shape);
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < hull->getNumPoints(); ++i) points.push_back(to_eigen(hull->getScaledPoint(i)));
    const auto built = collision::ConvexPolyhedron::build(points);
    if (!built.ok()) return nullptr;
    made->shape = collision::Polyhedron{built.polyhedron, hull->getMargin()};
    made->offset = built.polyhedron->offset();
  } else if (!primitive_shape(shape, made->shape)) {
    return nullptr;
  }
  return shapes_.emplace(shape, std::move(made)).first->second.get();
}

void ShapeCache::set(const btCollisionShape* bullet, const CachedShape& shape) {
  std::lock_guard<std::mutex> lock(mutex_);
  shapes_[bullet] = std::make_unique<CachedShape>(shape);
}

HedraCollisionAlgorithm::HedraCollisionAlgorithm(const btCollisionAlgorithmConstructionInfo& ci,
                                                 const btCollisionObjectWrapper* a, const btCollisionObjectWrapper* b,
                                                 ShapeCache* shapes, ManifoldUpdate update)
    : btActivatingCollisionAlgorithm(ci, a, b), shapes_(shapes), update_(update) {
  if (m_dispatcher->needsCollision(a->getCollisionObject(), b->getCollisionObject())) {
    manifold_ = m_dispatcher->getNewManifold(a->getCollisionObject(), b->getCollisionObject());
    own_manifold_ = true;
  }
}

HedraCollisionAlgorithm::~HedraCollisionAlgorithm() {
  if (own_manifold_ && manifold_) m_dispatcher->releaseManifold(manifold_);
}

void HedraCollisionAlgorithm::processCollision(const btCollisionObjectWrapper* a, const btCollisionObjectWrapper* b,
                                               const btDispatcherInfo& info, btManifoldResult* result) {
  if (!manifold_) return;
  result->setPersistentManifold(manifold_);
  // The pair's two hedra shapes, looked up (under the cache's lock) only
  // when a Bullet shape changes.
  if (a->getCollisionShape() != bullet_a_ || b->getCollisionShape() != bullet_b_) {
    bullet_a_ = a->getCollisionShape();
    bullet_b_ = b->getCollisionShape();
    shape_a_ = shapes_->get(bullet_a_);
    shape_b_ = shapes_->get(bullet_b_);
    radius_a_ = origin_radius(bullet_a_);
    radius_b_ = origin_radius(bullet_b_);
  }
  const CachedShape* sa = shape_a_;
  const CachedShape* sb = shape_b_;
  if (!sa || !sb) return;
  collision::ContactSettings settings;
  settings.contact_distance = speculative_distance(a->getCollisionObject(), b->getCollisionObject(), info);
  const collision::ContactResult r = collision::contact(sa->shape, sa->pose(a->getWorldTransform()), sb->shape,
                                                        sb->pose(b->getWorldTransform()), &cache_, settings);
  ++g_queries;
  int order[collision::kMaxContactPoints];
  polygon_order(r, order);
  g_points += r.count;
  if (update_ == ManifoldUpdate::keep_new) {
    merge_points(r, order, a->getCollisionObject(), *manifold_);  // refreshes the manifold once
    return;
  }
  for (int i = 0; i < r.count; ++i) {  // Bullet's own merge, a point at a time, then its refresh
    const collision::ContactPoint& p = r.points[order[i]];
    const Eigen::Vector3d on_b = p.point - 0.5 * p.depth * r.normal;
    result->addContactPoint(to_bullet(-r.normal), to_bullet(on_b), -p.depth);
  }
  result->refreshContactPoints();
}

double HedraCollisionAlgorithm::speculative_distance(const btCollisionObject* a, const btCollisionObject* b,
                                                     const btDispatcherInfo& info) const {
  const double threshold = manifold_->getContactBreakingThreshold();
  const double dt = info.m_timeStep;
  if (!(dt > 0.0)) return threshold;
  return std::min(threshold, reach(a, radius_a_, dt) + reach(b, radius_b_, dt));
}

long HedraCollisionAlgorithm::queries() { return g_queries.load(); }
long HedraCollisionAlgorithm::points() { return g_points.load(); }

void register_hedra(btCollisionDispatcher& dispatcher, HedraCollisionAlgorithm::CreateFunc& create,
                    ShapeCache& shapes) {
  create.shapes = &shapes;
  const int types[] = {BOX_SHAPE_PROXYTYPE,     CONVEX_HULL_SHAPE_PROXYTYPE, SPHERE_SHAPE_PROXYTYPE,
                       CAPSULE_SHAPE_PROXYTYPE, CYLINDER_SHAPE_PROXYTYPE,    CONE_SHAPE_PROXYTYPE};
  for (const int x : types)
    for (const int y : types) dispatcher.registerCollisionCreateFunc(x, y, &create);
}

}  // namespace hedra::simulate
