// The plain-C boundary of Bullet's own per-pair narrowphase
// (bullet_dispatch_module.cpp, compiled into both Bullet modules beside
// bullet_module.cpp): the algorithm btCollisionDispatcher picks for the
// pair under btDefaultCollisionConfiguration (btConvexConvexAlgorithm,
// btSphereBoxCollisionAlgorithm, btBoxBoxCollisionAlgorithm, ...), run as a
// world runs it each frame: processCollision into the pair's
// btPersistentManifold, kept across frames (warm) or the algorithm and its
// manifold made anew for the query (cold). Shapes as bullet_module.h
// describes them; `polyhedral` calls initializePolyhedralFeatures() on
// boxes and hulls (btConvexConvexAlgorithm then clips faces instead of
// adding one GJK/EPA point a frame).
#pragma once

#include "bullet_module.h"

extern "C" {

struct HedraBulletDispatchResult {
  int points;          // contact points in the pair's manifold after the call
  double deepest;      // the smallest distance among them (< 0 penetration)
  char algorithm[96];  // the algorithm's class (demangled)
};

typedef void* (*HedraBulletDispatchPrepare)(const HedraBulletShape* a, const HedraBulletShape* b, int polyhedral);
// pose_a, pose_b: 12 doubles each (row-major rotation, then the shape's origin).
typedef void (*HedraBulletDispatchQuery)(void* prepared, const double* pose_a, const double* pose_b, int warm,
                                         HedraBulletDispatchResult* out);
typedef void (*HedraBulletDispatchRelease)(void* prepared);
}
