// Time of impact of two shapes moving with rotation over a step.
//
//   time_of_impact(a, sweep_a, b, sweep_b, cache, settings)
//
// A Sweep moves a body from its start pose to its end pose over t in [0, 1]:
// its origin (the shape's local origin) linearly, its orientation about that
// origin at a constant angular velocity along the shorter arc (slerp). The
// answer is the first t at which the distance is <= target = target_distance
// + linear_slop.
//
// Conservative advancement (Mirtich 1996) on certified bounds. At the current
// t, GJK gives the cores' closest direction n (A toward B); the separation
// along n, s = min_B n . y - max_A n . x (two support calls; certified
// whatever GJK's status), bounds the distance from below. Along the motion,
// with n held fixed, a point of a body at distance <= r from its origin
// moves along n at most as fast as n . (its origin's velocity) + |n x w| r,
// w the angular velocity, so
//   d(t + dt) >= s - dt c,  c = -n . (v_b - v_a) + |n x w_a| r_a + |n x w_b| r_b,
// r the body's largest distance from its origin (margin included). The step
// dt = (s - target) / c therefore never passes the first contact; c <= 0 or
// t + dt > 1 proves the pair stays apart. The loop ends when GJK's distance
// (an upper bound) is within the tolerance of the target: the distance at t
// lies in [target, target + tolerance].
//
// Frames: positions are taken relative to A's start position (exact for
// nearby bodies), so bodies 1e6 from the origin lose nothing; GJK runs on
// the cores in A's core frame at t, as the other queries do. Pairs within
// the target at t = 0 answer t = 0 with penetration()'s signed answer; so
// do pairs whose first GJK bracket straddles the target (rounding on a thin
// core) when penetration() finds them possibly within it; beyond it, the
// stall at t = 0 is certified free.
#pragma once

#include <Eigen/Core>
#include <hedra/collision/cast_result.hpp>
#include <hedra/collision/query.hpp>
#include <hedra/collision/shapes.hpp>

namespace hedra::collision {

struct Sweep {
  Pose start;  // the pose at t = 0
  Pose end;    // the pose at t = 1
};

// The pose at t in [0, 1]: origin linear, rotation R(t) = exp(t theta k) R0,
// theta k the shorter rotation from start to end (theta in [0, pi]).
Pose pose_at(const Sweep& sweep, double t);

struct ToiSettings {
  // Contact when the distance is <= target_distance + linear_slop (both >= 0;
  // default: touching).
  double target_distance = 0.0;
  double linear_slop = 0.0;
  // A hit's distance is within tolerance * size above the target (size: the
  // larger bounding radius), and never below the rounding of the pair's
  // coordinates (32 eps (size + the distance travelled)). The larger body
  // sets the scale, as GJK's own tolerance does: a 1e-3 body against a 1e3
  // one stops up to 1.7e-6 from the target, 1.7e-3 of the small body. A
  // caller who needs the small body's scale lowers this and gjk's two
  // tolerances together (1e-13 and 1e-14 there: within 1.7e-7 of the small
  // body, a step or two more); the rounding of the large body's coordinates
  // is the floor.
  double tolerance = 1e-9;
  // Advancement steps. Each one costs a GJK query; the steps shrink
  // geometrically with the ratio of the true closing speed to its bound
  // (one step for faces meeting head on, tens with rotation, more for
  // rotating bodies that pass within a hair of each other).
  int max_iterations = 256;
  GjkSettings gjk;  // each step's GJK (its tolerance must stay below the one above)
};

// `cache` (optional): the last separating axis and polyhedron support hints
// (A's core frame), the warm start of the first step; one per pair and thread.
CastResult time_of_impact(const Shape& a, const Sweep& sweep_a, const Shape& b, const Sweep& sweep_b,
                          GjkCache* cache = nullptr, const ToiSettings& settings = {});

}  // namespace hedra::collision
