// The three scenes that put hedra's manifolds inside a real simulator, run in
// Bullet's btDiscreteDynamicsWorld with either hedra's narrowphase
// (hedra_collision_algorithm.hpp) or Bullet's own, and measured the same way:
//
//   stack    10 unit boxes stacked on a static ground box, exactly touching;
//   pyramid  a 4-level pyramid of unit boxes (4, 3, 2, 1 in the x-z plane,
//            2 cm apart in a row, each level on the gaps of the one below);
//   pile     20 random convex hulls (12 points on an ellipsoid of semi-axes
//            0.25..0.5, seeded) dropped from a 2 x 2 x 5 grid onto the ground.
//
// World: gravity 9.81 along -z, fixed 60 Hz steps (one substep), 50 solver
// iterations (a tall stack needs more than Bullet's default 10), friction
// anchors on every dynamic body (btCollisionObject::CF_HAS_FRICTION_ANCHOR:
// a contact point whose friction stays inside the Coulomb cone keeps its
// anchor instead of being replaced each step; without it a resting stack
// creeps sideways with either narrowphase), Bullet's default sleeping.
// Every setting is the same for both narrowphases: only the collision
// algorithms of box and hull pairs differ.
//
// Measures (SceneReport): the top body's sideways drift, late creep, jitter,
// the deepest interpenetration at the end (the exact reference of
// tools/reference, between every pair of bodies including the ground),
// contact counts
// and the median wall time of a step.
#pragma once

#include <string>

namespace hedra::simulate {

enum class SceneKind { stack, pyramid, pile };
enum class Narrowphase { hedra, bullet };

const char* to_string(SceneKind scene);
const char* to_string(Narrowphase narrowphase);
// False for an unknown name.
bool parse(const std::string& name, SceneKind& scene);
bool parse(const std::string& name, Narrowphase& narrowphase);

struct SceneSettings {
  SceneKind scene = SceneKind::stack;
  Narrowphase narrowphase = Narrowphase::hedra;
  double seconds = 10.0;  // simulated time
  double hz = 60.0;       // fixed step rate
  bool sleeping = true;   // Bullet's deactivation (false: every body stays awake)
  bool anchors = true;    // friction anchors on the dynamic bodies
  unsigned seed = 1;      // the pile's hulls and poses
  int solver_iterations = 50;
};

struct SceneReport {
  int bodies = 0;     // dynamic bodies
  double size = 0.0;  // the smallest body size (shortest local extent), metres
  int steps = 0;
  // Horizontal displacement of the top body (highest at the start) from its
  // start, metres; the pile has no top body (0).
  double top_drift = 0.0;
  // Largest displacement of any body over the last half of the run, metres
  // (a settled scene: ~0; a creeping one: its creep).
  double late_creep = 0.0;
  // RMS over the last second of every dynamic body's linear speed, sampled
  // after each step, m/s (sleeping bodies count as 0).
  double jitter = 0.0;
  // At the end: the deepest interpenetration of any pair of bodies
  // (ground included) divided by the smaller body's size.
  double max_penetration = 0.0;
  // At the end: the lowest point of any body relative to the ground's top,
  // divided by that body's size (< 0: sunk into the ground).
  double lowest_above_ground = 0.0;
  double max_speed = 0.0;  // largest linear speed at the end, m/s
  int asleep = 0;          // bodies deactivated at the end
  // Contact points per non-empty manifold and non-empty manifolds per step,
  // averaged over all steps.
  double points_per_manifold = 0.0;
  double manifolds_per_step = 0.0;
  double median_step_us = 0.0;  // median wall time of a stepSimulation call, over the steps with a body awake
  long hedra_queries = 0;       // contact() calls made by hedra's algorithm
  int measure_failures = 0;     // pairs the exact reference could not measure (0 expected)
};

SceneReport run_scene(const SceneSettings& settings);

}  // namespace hedra::simulate
