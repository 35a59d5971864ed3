// One Bullet 3.24 build behind bullet_module.h (see there): distances,
// contact manifolds and times of impact. Shapes are
// Bullet's own primitives and btConvexHullShape; every collision margin is
// set to hedra's margin (0 by default, where Bullet's default is 0.04), and
// where Bullet keeps the outer size fixed on setMargin (box, cylinder) the
// shape is built at core + margin so that its core stays hedra's.
//
// btGjkPairDetector reports a normal "on B" pointing from B toward A and the
// point on B; hedra's normal is its negation and point_a = point_b +
// distance * normal_on_b. btGjkEpaSolver2::SignedDistance reports its normal
// in A's local frame (field-notes.md): it is rotated to world here.
#include "bullet_module.h"

#include <BulletCollision/NarrowPhaseCollision/btContinuousConvexCollision.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkConvexCast.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpa2.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btPointCollector.h>
#include <BulletCollision/NarrowPhaseCollision/btPolyhedralContactClipping.h>
#include <BulletCollision/NarrowPhaseCollision/btSubSimplexConvexCast.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>
#include <btBulletCollisionCommon.h>

#include <cmath>
#include <cstdio>
#include <memory>

namespace {

std::unique_ptr<btConvexShape> make_shape(const HedraBulletShape& s) {
  const btScalar m = static_cast<btScalar>(s.margin);
  std::unique_ptr<btConvexShape> shape;
  switch (s.kind) {
    case hedra_bullet_sphere:
      shape = std::make_unique<btSphereShape>(static_cast<btScalar>(s.radius + s.margin));
      return shape;
    case hedra_bullet_capsule:
      shape = std::make_unique<btCapsuleShapeZ>(static_cast<btScalar>(s.radius + s.margin),
                                                static_cast<btScalar>(2.0 * s.half_length));
      return shape;
    case hedra_bullet_box:
      shape = std::make_unique<btBoxShape>(btVector3(static_cast<btScalar>(s.half_extents[0] + s.margin),
                                                     static_cast<btScalar>(s.half_extents[1] + s.margin),
                                                     static_cast<btScalar>(s.half_extents[2] + s.margin)));
      break;
    case hedra_bullet_cylinder:
      shape = std::make_unique<btCylinderShapeZ>(btVector3(static_cast<btScalar>(s.radius + s.margin),
                                                           static_cast<btScalar>(s.radius + s.margin),
                                                           static_cast<btScalar>(s.half_length + s.margin)));
      break;
    case hedra_bullet_cone:
      shape =
          std::make_unique<btConeShapeZ>(static_cast<btScalar>(s.radius), static_cast<btScalar>(2.0 * s.half_length));
      break;
    default: {
      auto hull = std::make_unique<btConvexHullShape>();
      for (size_t i = 0; i < s.point_count; ++i)
        hull->addPoint(btVector3(static_cast<btScalar>(s.points[3 * i]), static_cast<btScalar>(s.points[3 * i + 1]),
                                 static_cast<btScalar>(s.points[3 * i + 2])),
                       false);
      hull->recalcLocalAabb();
      shape = std::move(hull);
    }
  }
  shape->setMargin(m);
  return shape;
}

btTransform make_transform(const HedraBulletShape& s) {
  const auto c = [&](int i) { return static_cast<btScalar>(s.rotation[i]); };
  btMatrix3x3 basis(c(0), c(1), c(2), c(3), c(4), c(5), c(6), c(7), c(8));
  return btTransform(basis, btVector3(static_cast<btScalar>(s.translation[0]), static_cast<btScalar>(s.translation[1]),
                                      static_cast<btScalar>(s.translation[2])));
}

void store(const btVector3& v, double* out) {
  for (int k = 0; k < 3; ++k) out[k] = static_cast<double>(v[k]);
}

struct Prepared {
  std::unique_ptr<btConvexShape> a, b;
  btTransform ta, tb;
  int method = 0;
};

void finish(HedraBulletResult* out) {
  bool finite = std::isfinite(out->distance);
  for (int k = 0; k < 3; ++k)
    finite =
        finite && std::isfinite(out->normal[k]) && std::isfinite(out->point_a[k]) && std::isfinite(out->point_b[k]);
  out->ok = finite;
  std::snprintf(out->status, sizeof(out->status), "%s", finite ? "ok" : "Bullet returned a non-finite value");
}

void query_pair_detector(Prepared& p, int query, HedraBulletResult* out) {
  btVoronoiSimplexSolver simplex;
  btGjkEpaPenetrationDepthSolver epa;
  btGjkPairDetector gjk(p.a.get(), p.b.get(), &simplex, &epa);
  btGjkPairDetector::ClosestPointInput input;
  input.m_transformA = p.ta;
  input.m_transformB = p.tb;
  btPointCollector collector;
  gjk.getClosestPoints(input, collector, nullptr);
  if (!collector.m_hasResult) {
    std::snprintf(out->status, sizeof(out->status), "btGjkPairDetector: no result");
    return;
  }
  const double d = static_cast<double>(collector.m_distance);
  const btVector3 n = -collector.m_normalOnBInWorld;
  const btVector3 pb = collector.m_pointInWorld;
  const btVector3 pa = pb + collector.m_normalOnBInWorld * collector.m_distance;
  out->intersecting = d <= 0.0;
  out->has_distance = query != 0;
  out->distance = query == 1 && d < 0.0 ? 0.0 : d;
  store(n, out->normal);
  store(pa, out->point_a);
  store(pb, out->point_b);
  finish(out);
}

void query_signed_distance(Prepared& p, int query, HedraBulletResult* out) {
  btGjkEpaSolver2::sResults results;
  const btVector3 guess = p.tb.getOrigin() - p.ta.getOrigin();
  const bool answered = btGjkEpaSolver2::SignedDistance(p.a.get(), p.ta, p.b.get(), p.tb, guess, results);
  if (!answered) {
    std::snprintf(out->status, sizeof(out->status), "btGjkEpaSolver2::SignedDistance failed (status %d)",
                  static_cast<int>(results.status));
    return;
  }
  // SignedDistance works on the cores (no margins: a sphere is its centre)
  // and its normal points from B toward A in A's frame.
  const btScalar ma = p.a->getMargin(), mb = p.b->getMargin();
  const btVector3 n = -(p.ta.getBasis() * results.normal);
  const double d = static_cast<double>(results.distance - ma - mb);
  out->intersecting = d <= 0.0;
  out->has_distance = query != 0;
  out->distance = query == 1 && d < 0.0 ? 0.0 : d;
  store(n, out->normal);
  store(results.witnesses[0] + ma * n, out->point_a);
  store(results.witnesses[1] - mb * n, out->point_b);
  finish(out);
}

// The polyhedral contact path (bullet_module.h).
struct PreparedManifold {
  std::unique_ptr<btConvexShape> a, b;
  btTransform ta, tb;
  bool polyhedral = false;
  btVertexArray verts_1, verts_2;  // Bullet's clipping buffers, kept like btConvexConvexAlgorithm keeps them
};

struct ContactCollector final : btDiscreteCollisionDetectorInterface::Result {
  HedraBulletContacts* out = nullptr;
  void setShapeIdentifiersA(int, int) override {}
  void setShapeIdentifiersB(int, int) override {}
  void addContactPoint(const btVector3& normal_on_b, const btVector3& point, btScalar depth) override {
    if (out->count < HEDRA_BULLET_MAX_CONTACTS) {
      store(normal_on_b, out->normal_on_b[out->count]);
      store(point, out->point[out->count]);
      out->distance[out->count] = static_cast<double>(depth);
      ++out->count;
    }
    ++out->total;
  }
};

// Time of impact (bullet_module.h): the shapes at the start, both end transforms.
struct PreparedToi {
  std::unique_ptr<btConvexShape> a, b;
  btTransform a0, a1, b0, b1;
  int method = 2;
};

bool cast(PreparedToi& p, btConvexCast::CastResult& result) {
  btVoronoiSimplexSolver simplex;
  if (p.method == 0) {
    btGjkConvexCast c(p.a.get(), p.b.get(), &simplex);
    return c.calcTimeOfImpact(p.a0, p.a1, p.b0, p.b1, result);
  }
  if (p.method == 1) {
    btSubsimplexConvexCast c(p.a.get(), p.b.get(), &simplex);
    return c.calcTimeOfImpact(p.a0, p.a1, p.b0, p.b1, result);
  }
  btGjkEpaPenetrationDepthSolver epa;
  btContinuousConvexCollision c(p.a.get(), p.b.get(), &simplex, &epa);
  return c.calcTimeOfImpact(p.a0, p.a1, p.b0, p.b1, result);
}

const btConvexPolyhedron* polyhedron_of(const btConvexShape* s) {
  return static_cast<const btPolyhedralConvexShape*>(s)->getConvexPolyhedron();
}

// A pair detector kept across frames (see bullet_module.h).
struct PreparedMoving {
  std::unique_ptr<btConvexShape> a, b;
  btVoronoiSimplexSolver simplex;
  btGjkEpaPenetrationDepthSolver epa;
  std::unique_ptr<btGjkPairDetector> gjk;
};

btTransform transform_of(const double* pose) {
  const auto c = [&](int i) { return static_cast<btScalar>(pose[i]); };
  return btTransform(btMatrix3x3(c(0), c(1), c(2), c(3), c(4), c(5), c(6), c(7), c(8)), btVector3(c(9), c(10), c(11)));
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) void* hedra_bullet_moving_prepare(const HedraBulletShape* a,
                                                                         const HedraBulletShape* b) {
  auto* p = new PreparedMoving;
  p->a = make_shape(*a);
  p->b = make_shape(*b);
  p->gjk = std::make_unique<btGjkPairDetector>(p->a.get(), p->b.get(), &p->simplex, &p->epa);
  return p;
}

__attribute__((visibility("default"))) void hedra_bullet_moving_query(void* prepared, const double* pose_a,
                                                                      const double* pose_b, int warm,
                                                                      HedraBulletResult* out) {
  *out = HedraBulletResult{};
  out->distance = NAN;
  auto& p = *static_cast<PreparedMoving*>(prepared);
  if (!warm) p.gjk->setCachedSeparatingAxis(btVector3(0, 1, 0));
  btGjkPairDetector::ClosestPointInput input;
  input.m_transformA = transform_of(pose_a);
  input.m_transformB = transform_of(pose_b);
  btPointCollector collector;
  p.gjk->getClosestPoints(input, collector, nullptr);
  if (!collector.m_hasResult) {
    std::snprintf(out->status, sizeof(out->status), "btGjkPairDetector: no result");
    return;
  }
  const double d = static_cast<double>(collector.m_distance);
  const btVector3 pb = collector.m_pointInWorld;
  out->intersecting = d <= 0.0;
  out->has_distance = 1;
  out->distance = d;
  store(-collector.m_normalOnBInWorld, out->normal);
  store(pb + collector.m_normalOnBInWorld * collector.m_distance, out->point_a);
  store(pb, out->point_b);
  finish(out);
}

__attribute__((visibility("default"))) void hedra_bullet_moving_release(void* prepared) {
  delete static_cast<PreparedMoving*>(prepared);
}

__attribute__((visibility("default"))) void* hedra_bullet_prepare(const HedraBulletShape* a, const HedraBulletShape* b,
                                                                  int method) {
  auto* p = new Prepared;
  p->a = make_shape(*a);
  p->b = make_shape(*b);
  p->ta = make_transform(*a);
  p->tb = make_transform(*b);
  p->method = method;
  return p;
}

__attribute__((visibility("default"))) void hedra_bullet_query(void* prepared, int query, HedraBulletResult* out) {
  *out = HedraBulletResult{};
  out->distance = NAN;
  auto& p = *static_cast<Prepared*>(prepared);
  if (p.method == 0)
    query_pair_detector(p, query, out);
  else
    query_signed_distance(p, query, out);
}

__attribute__((visibility("default"))) void hedra_bullet_release(void* prepared) {
  delete static_cast<Prepared*>(prepared);
}

__attribute__((visibility("default"))) void* hedra_bullet_manifold_prepare(const HedraBulletShape* a,
                                                                           const HedraBulletShape* b) {
  auto* p = new PreparedManifold;
  p->a = make_shape(*a);
  p->b = make_shape(*b);
  p->ta = make_transform(*a);
  p->tb = make_transform(*b);
  const auto polyhedral = [](const HedraBulletShape& s) {
    return s.kind == hedra_bullet_box || s.kind == hedra_bullet_hull;
  };
  p->polyhedral = polyhedral(*a) && polyhedral(*b);
  if (p->polyhedral) {
    static_cast<btPolyhedralConvexShape*>(p->a.get())->initializePolyhedralFeatures();
    static_cast<btPolyhedralConvexShape*>(p->b.get())->initializePolyhedralFeatures();
  }
  return p;
}

__attribute__((visibility("default"))) void hedra_bullet_manifold_query(void* prepared, double max_distance,
                                                                        HedraBulletContacts* out) {
  auto& p = *static_cast<PreparedManifold*>(prepared);
  out->supported = p.polyhedral ? 1 : 0;
  out->separated = 0;
  out->count = out->total = 0;
  if (!p.polyhedral) return;
  ContactCollector collector;
  collector.out = out;
  btVector3 sep(0, 0, 0);
  const btConvexPolyhedron* pa = polyhedron_of(p.a.get());
  const btConvexPolyhedron* pb = polyhedron_of(p.b.get());
  if (!btPolyhedralContactClipping::findSeparatingAxis(*pa, *pb, p.ta, p.tb, sep, collector)) {
    out->separated = 1;
    return;
  }
  btPolyhedralContactClipping::clipHullAgainstHull(
      sep, *pa, *pb, p.ta, p.tb, btScalar(-1e30), static_cast<btScalar>(max_distance), p.verts_1, p.verts_2, collector);
}

__attribute__((visibility("default"))) void hedra_bullet_manifold_release(void* prepared) {
  delete static_cast<PreparedManifold*>(prepared);
}
__attribute__((visibility("default"))) void* hedra_bullet_toi_prepare(const HedraBulletShape* a,
                                                                      const HedraBulletShape* a_end,
                                                                      const HedraBulletShape* b,
                                                                      const HedraBulletShape* b_end, int method) {
  auto* p = new PreparedToi;
  p->a = make_shape(*a);
  p->b = make_shape(*b);
  p->a0 = make_transform(*a);
  p->a1 = make_transform(*a_end);
  p->b0 = make_transform(*b);
  p->b1 = make_transform(*b_end);
  p->method = method;
  return p;
}

__attribute__((visibility("default"))) void hedra_bullet_toi_query(void* prepared, HedraBulletToiResult* out) {
  *out = HedraBulletToiResult{};
  btConvexCast::CastResult result;
  const bool hit = cast(*static_cast<PreparedToi*>(prepared), result);
  out->hit = hit ? 1 : 0;
  out->fraction = hit ? static_cast<double>(result.m_fraction) : 1.0;
  out->ok = std::isfinite(out->fraction) ? 1 : 0;
  std::snprintf(out->status, sizeof(out->status), "%s", out->ok ? "ok" : "Bullet returned a non-finite fraction");
}

__attribute__((visibility("default"))) void hedra_bullet_toi_release(void* prepared) {
  delete static_cast<PreparedToi*>(prepared);
}
}
