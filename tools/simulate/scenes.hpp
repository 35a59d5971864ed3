// The scenes that put hedra's manifolds inside a real simulator, run in
// Bullet's btDiscreteDynamicsWorld with either hedra's narrowphase
// (hedra_collision_algorithm.hpp) or Bullet's own, and measured the same way.
// Every body rests on a static ground box whose top face is z = 0 (40 x 40 m,
// 100 x 100 m for tiny-on-ground); unit boxes have Bullet's default margin.
//
//   stack, stack-20, stack-30   10, 20, 30 unit boxes stacked, exactly touching;
//   pyramid   a 4-level pyramid of unit boxes (4, 3, 2, 1 in the x-z plane,
//             2 cm apart in a row, each level on the gaps of the one below);
//   pile      20 random convex hulls (12 points on an ellipsoid of semi-axes
//             0.25..0.5, seeded, Bullet's default margin 0.04) dropped from a
//             2 x 2 x 5 grid; pile-60, pile-60-rounded: 60 such hulls from a
//             3 x 4 x 5 grid, sharp (margin 0) or rounded by 2 % to 10 % of
//             the hull's smallest extent;
//   mass-100, mass-1000   a 1 kg unit box under a 100 kg (1,000 kg) one;
//   plates    ten 1 x 1 x 0.01 m plates; plate-1mm: a 0.5 x 0.5 x 0.001 m
//             plate on a unit box;
//   far-1e4, far-1e5   the 10-box stack, ground included, 1e4 m (1e5 m)
//             from the origin along (1, 1, 1);
//   tiny-on-ground, tiny-on-box   five 2 cm boxes stacked on a 100 m ground,
//             on a unit box;
//   rounded-boxes   five rounded boxes (core 0.9 m, margin 0.05: Bullet sees
//             the hull of the core's corners rounded by the margin, hedra a
//             Box with that margin); rounded-hulls: five hexagonal prisms
//             (0.45 m radius, 0.4 m tall, margin 0.05);
//   capsule-, cylinder-lying/-standing, cone-standing, sphere-on-box: a
//             capsule (radius 0.2, 0.6 m segment), cylinder (radius 0.3,
//             0.8 m tall, Bullet's margin), cone (radius 0.3, 0.8 m tall,
//             margin 0.01) or sphere (radius 0.3) on a unit box.
// Every body weighs 1 kg but the heavy boxes of mass-100 and mass-1000.
//
// World: gravity 9.81 along -z, fixed 60 Hz steps (one substep), 50 solver
// iterations (a tall stack needs more than Bullet's default 10), friction
// anchors on every dynamic box and hull (btCollisionObject::CF_HAS_FRICTION_ANCHOR:
// a contact point whose friction stays inside the Coulomb cone keeps its
// anchor instead of being replaced each step; without it a resting stack
// creeps sideways with either narrowphase), Bullet's default sleeping.
// Every setting is the same for both narrowphases: only the collision
// algorithms of the convex pairs differ. A perturbed start moves every
// dynamic body sideways by up to `perturbation` of its size and turns it
// about z by up to `perturbation` rad (seeded; nothing starts overlapping).
//
// Measures (SceneReport): the top body's sideways drift, late creep, jitter,
// the deepest interpenetration at the end (the exact reference of
// tools/reference, between every pair of bodies whose bounding boxes meet,
// ground included), whether a built scene still stands, NaN and explosions,
// contact counts and the median wall time of a step.
#pragma once

#include <string>
#include <vector>

namespace hedra::simulate {

enum class SceneKind {
  stack,
  pyramid,
  pile,
  stack_20,
  stack_30,
  mass_100,
  mass_1000,
  plates,
  plate_1mm,
  pile_60,
  pile_60_rounded,
  far_1e4,
  far_1e5,
  tiny_on_ground,
  tiny_on_box,
  rounded_boxes,
  rounded_hulls,
  capsule_lying,
  capsule_standing,
  cylinder_lying,
  cylinder_standing,
  cone_standing,
  sphere_on_box,
};
enum class Narrowphase { hedra, bullet };

const char* to_string(SceneKind scene);
const char* to_string(Narrowphase narrowphase);
// False for an unknown name.
bool parse(const std::string& name, SceneKind& scene);
bool parse(const std::string& name, Narrowphase& narrowphase);
// The stiff and extreme scenes (every kind after pile), in table order.
std::vector<SceneKind> stiff_scenes();

struct SceneSettings {
  SceneKind scene = SceneKind::stack;
  Narrowphase narrowphase = Narrowphase::hedra;
  double seconds = 10.0;      // simulated time
  double hz = 60.0;           // fixed step rate
  bool sleeping = true;       // Bullet's deactivation (false: every body stays awake)
  bool anchors = true;        // friction anchors on the dynamic bodies
  unsigned seed = 1;          // the piles' hulls and the perturbation
  double perturbation = 0.0;  // the start's sideways offset (fraction of a body's size) and turn (rad)
  int solver_iterations = 50;
  // hedra's points merged by Bullet's btManifoldResult::addContactPoint
  // instead of ManifoldUpdate::keep_new (hedra_collision_algorithm.hpp).
  bool bullet_merge = false;
};

struct SceneReport {
  int bodies = 0;     // dynamic bodies
  double size = 0.0;  // the smallest body size (shortest local extent), metres
  int steps = 0;
  // Horizontal displacement of the top body (highest at the start) from its
  // start, metres, and that body's size; the piles have no top body (0).
  double top_drift = 0.0;
  double top_size = 0.0;
  // A built scene (not a pile) stands when every dynamic body ends sideways
  // within a quarter of its largest extent of its start, turned by less than
  // 0.2 rad.
  bool built = false;
  bool stands = false;
  bool non_finite = false;  // a NaN or infinity in any body's pose or velocity after any step
  bool exploded = false;    // a body faster than 20 m/s after any step
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
