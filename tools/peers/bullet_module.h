// The plain-C boundary between hedra_peers and its two Bullet modules
// (bullet_module.cpp compiled once against libBulletCollision.so and once,
// with BT_USE_DOUBLE_PRECISION, against libBulletCollision-float64.so). Only
// plain data crosses it, so neither module needs hedra or Eigen, and the two
// Bullet builds never share a symbol scope (each module is dlopen'ed with
// RTLD_LOCAL).
#pragma once

#include <stddef.h>

extern "C" {

enum HedraBulletKind {
  hedra_bullet_sphere,
  hedra_bullet_box,
  hedra_bullet_capsule,
  hedra_bullet_cylinder,
  hedra_bullet_cone,
  hedra_bullet_hull
};

struct HedraBulletShape {
  int kind;
  double radius, half_length, half_extents[3], margin;
  const double* points;  // hull vertices, xyz packed, in the hull's frame
  size_t point_count;
  double rotation[9];     // row-major world rotation
  double translation[3];  // world position of the shape's (hull's) origin
};

struct HedraBulletResult {
  int ok, intersecting, has_distance;
  double distance, normal[3], point_a[3], point_b[3];
  char status[160];
};

// method: 0 = btGjkPairDetector + btGjkEpaPenetrationDepthSolver,
//         1 = btGjkEpaSolver2::SignedDistance.
// query:  0 = intersect, 1 = distance, 2 = penetration (hedra::peers::PeerQuery).
typedef void* (*HedraBulletPrepare)(const HedraBulletShape* a, const HedraBulletShape* b, int method);
typedef void (*HedraBulletQuery)(void* prepared, int query, HedraBulletResult* out);
typedef void (*HedraBulletRelease)(void* prepared);

// Contact manifolds through Bullet's polyhedral path, as
// btConvexConvexAlgorithm runs it for two polyhedral shapes (boxes and hulls
// with initializePolyhedralFeatures()):
// btPolyhedralContactClipping::findSeparatingAxis, then clipHullAgainstHull
// with minDist = -1e30 and maxDist = max_distance. Every point Bullet reports
// is kept (Bullet reduces them later, in btPersistentManifold): the first
// HEDRA_BULLET_MAX_CONTACTS are stored, `total` counts all of them.
#define HEDRA_BULLET_MAX_CONTACTS 64
struct HedraBulletContacts {
  int supported;  // both shapes polyhedral (box or hull)
  int separated;  // findSeparatingAxis found a separating axis (no points)
  int count, total;
  // Bullet's own convention: normal_on_b as reported, point in world (on B's
  // incident face for clipped points), distance (< 0 penetration).
  double normal_on_b[HEDRA_BULLET_MAX_CONTACTS][3];
  double point[HEDRA_BULLET_MAX_CONTACTS][3];
  double distance[HEDRA_BULLET_MAX_CONTACTS];
};
typedef void* (*HedraBulletManifoldPrepare)(const HedraBulletShape* a, const HedraBulletShape* b);
typedef void (*HedraBulletManifoldQuery)(void* prepared, double max_distance, HedraBulletContacts* out);
typedef void (*HedraBulletManifoldRelease)(void* prepared);

// A btGjkPairDetector kept across frames, as btConvexConvexAlgorithm keeps
// one per pair: its cached separating axis carries over from one query to
// the next (warm), or is reset to Bullet's default (0, 1, 0) first (cold).
// pose_a, pose_b: 12 doubles each, the row-major world rotation then the
// world position of the shape's (hull's) origin. The answer as
// hedra_bullet_query's penetration query gives it.
typedef void* (*HedraBulletMovingPrepare)(const HedraBulletShape* a, const HedraBulletShape* b);
typedef void (*HedraBulletMovingQuery)(void* prepared, const double* pose_a, const double* pose_b, int warm,
                                       HedraBulletResult* out);
typedef void (*HedraBulletMovingRelease)(void* prepared);

// Time of impact over a step: shapes at their start poses (a, b) and the
// end poses (rotation and translation of a_end, b_end). method: 0 =
// btGjkConvexCast, 1 = btSubsimplexConvexCast (both translation only),
// 2 = btContinuousConvexCollision (btGjkEpaPenetrationDepthSolver; with
// rotation). `hit` as calcTimeOfImpact returns it; fraction = m_fraction
// (1 without a hit).
struct HedraBulletToiResult {
  int ok, hit;
  double fraction;
  char status[160];
};
typedef void* (*HedraBulletToiPrepare)(const HedraBulletShape* a, const HedraBulletShape* a_end,
                                       const HedraBulletShape* b, const HedraBulletShape* b_end, int method);
typedef void (*HedraBulletToiQuery)(void* prepared, HedraBulletToiResult* out);
typedef void (*HedraBulletToiRelease)(void* prepared);
}
