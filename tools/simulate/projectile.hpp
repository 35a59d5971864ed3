// A fast projectile against a thin plate in Bullet's btDiscreteDynamicsWorld,
// with continuous collision by hedra's time_of_impact, by Bullet's own CCD,
// or none:
//
//   a 5 cm body (a sphere of radius 2.5 cm, or a cube of edge 5 cm spinning
//   at 30 rad/s) at 200 m/s straight down onto a static plate 2 m x 2 m,
//   1 cm thick (top face z = 0.005), from 1 m above; 60 Hz steps: 3.3 m a
//   step, 330 times the plate's thickness.
//
// Continuous collision:
//   none    Bullet's discrete detection only (the body passes through);
//   bullet  Bullet's CCD: setCcdMotionThreshold(size / 2) and
//           setCcdSweptSphereRadius(0.4 size), its sphere sweep clamping the
//           integrated motion;
//   hedra   after each step (Bullet's internal tick callback) each dynamic
//           body's motion over the step, start pose to end pose as a Sweep,
//           goes to time_of_impact against every static body; a hit clamps
//           the body to the pose at the time of impact, where it loses its
//           velocity into the plate and its spin (a sticking impact); a step
//           that starts touching is clamped where the body first gets 0.1 mm
//           deep (the time of impact against the plate shrunk by that much).
//           time_of_impact is never late, so a clamped pose never overlaps
//           the plate beyond that. Bullet's solver takes the contact from
//           there.
// The narrowphase is Bullet's own in every mode: only the continuous
// collision differs.
// Tunnelled: the body's centre crossed the plate's mid-plane inside its
// outline during a step (rolling off its edge later is not tunnelling).
#pragma once

namespace hedra::simulate {

enum class Projectile { sphere, box };
enum class Ccd { none, bullet, hedra };

const char* to_string(Projectile projectile);
const char* to_string(Ccd ccd);

struct ProjectileReport {
  bool tunnelled = false;
  double final_height = 0.0;  // the centre's z at the end, metres (the plate's top is 0.005)
  double deepest = 0.0;       // deepest penetration into the plate after any step, metres (exact: penetration())
  int clamps = 0;             // hedra: steps whose motion was clamped to a time of impact
  int steps = 0;
};

ProjectileReport run_projectile(Projectile projectile, Ccd ccd, double seconds = 0.25, double hz = 60.0);

}  // namespace hedra::simulate
