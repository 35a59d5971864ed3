// hedra_simulate: the reference example of embedding hedra in a simulator.
// Runs one of the scenes of scenes.hpp (stack, pyramid, pile) in Bullet's
// btDiscreteDynamicsWorld with hedra's narrowphase, Bullet's own, or both,
// and prints one table row per narrowphase:
//
//   hedra_simulate --scene stack --seconds 10 --narrowphase both
//
// Columns: top drift (the top body's sideways displacement from its start,
// metres and % of its size), late creep (largest displacement of any body
// over the second half), jitter (RMS linear speed over the last second),
// the deepest interpenetration at the end (% of the smaller body's size, by
// the exact reference of tools/reference), the lowest point above the ground (% of size),
// bodies asleep at the end, contact points per manifold and manifolds per
// step, and the median wall time of a step. Exit status 0, or 2 on bad
// arguments (the message says which).
//
//   hedra_simulate --scene projectile
//
// runs the fast projectile of projectile.hpp (a 5 cm sphere and a 5 cm cube
// at 200 m/s onto a 1 cm plate) with no continuous collision, Bullet's CCD
// and hedra's time of impact, one row each: tunnelled or not, the final
// height, the deepest penetration into the plate after any step.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "simulate/projectile.hpp"
#include "simulate/scenes.hpp"

int main(int argc, char** argv) {
  using namespace hedra::simulate;
  CLI::App app{"Run a scene in Bullet's btDiscreteDynamicsWorld with hedra's and/or Bullet's narrowphase"};
  std::string scene_name = "stack";
  std::string narrowphase_name = "both";
  SceneSettings settings;
  bool no_sleep = false;
  bool no_anchors = false;
  app.add_option("--scene", scene_name, "stack | pyramid | pile | projectile")->capture_default_str();
  app.add_option("--seconds", settings.seconds, "simulated time")->capture_default_str()->check(CLI::Range(0.0, 1e5));
  app.add_option("--hz", settings.hz, "fixed step rate")->capture_default_str()->check(CLI::Range(1.0, 1e5));
  app.add_option("--narrowphase", narrowphase_name, "hedra | bullet | both")->capture_default_str();
  app.add_option("--seed", settings.seed, "seed of the pile's hulls")->capture_default_str();
  app.add_option("--iterations", settings.solver_iterations, "solver iterations")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000));
  app.add_flag("--no-sleep", no_sleep, "keep every body awake (Bullet's deactivation off)");
  app.add_flag("--no-anchors", no_anchors, "no friction anchors");
  CLI11_PARSE(app, argc, argv);

  if (scene_name == "projectile") {
    std::printf("projectile: 5 cm body at 200 m/s onto a 1 cm plate, %.3g Hz, %.3g s\n\n", settings.hz,
                settings.seconds);
    std::printf("| body | continuous collision | tunnelled | final height m | deepest penetration m | clamps |\n");
    std::printf("|---|---|---|---|---|---|\n");
    for (const Projectile body : {Projectile::sphere, Projectile::box})
      for (const Ccd ccd : {Ccd::none, Ccd::bullet, Ccd::hedra}) {
        const ProjectileReport r = run_projectile(body, ccd, settings.seconds, settings.hz);
        std::printf("| %s | %s | %s | %.4f | %.2e | %d |\n", to_string(body), to_string(ccd),
                    r.tunnelled ? "yes" : "no", r.final_height, r.deepest, r.clamps);
      }
    return 0;
  }
  if (!parse(scene_name, settings.scene)) {
    std::fprintf(stderr, "hedra_simulate: --scene: unknown scene '%s' (stack, pyramid or pile)\n", scene_name.c_str());
    return 2;
  }
  std::vector<Narrowphase> narrowphases;
  Narrowphase one;
  if (narrowphase_name == "both") {
    narrowphases = {Narrowphase::hedra, Narrowphase::bullet};
  } else if (parse(narrowphase_name, one)) {
    narrowphases = {one};
  } else {
    std::fprintf(stderr, "hedra_simulate: --narrowphase: unknown narrowphase '%s' (hedra, bullet or both)\n",
                 narrowphase_name.c_str());
    return 2;
  }
  settings.sleeping = !no_sleep;
  settings.anchors = !no_anchors;

  std::printf("scene %s, %.3g s at %.3g Hz, %d solver iterations, sleeping %s, friction anchors %s\n\n",
              to_string(settings.scene), settings.seconds, settings.hz, settings.solver_iterations,
              settings.sleeping ? "on" : "off", settings.anchors ? "on" : "off");
  std::printf(
      "| narrowphase | top drift m (%% size) | late creep m | jitter m/s | max penetration %% size | lowest above "
      "ground %% size | asleep | points / manifold | manifolds / step | median step us |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Narrowphase narrowphase : narrowphases) {
    settings.narrowphase = narrowphase;
    const SceneReport r = run_scene(settings);
    if (r.measure_failures > 0)
      std::fprintf(stderr, "hedra_simulate: the exact reference failed on %d pairs (left out of max penetration)\n",
                   r.measure_failures);
    char drift[64] = "-";
    if (settings.scene != SceneKind::pile)
      std::snprintf(drift, sizeof drift, "%.2e (%.2f)", r.top_drift, 100.0 * r.top_drift / r.size);
    std::printf("| %s | %s | %.2e | %.2e | %.3f | %.3f | %d / %d | %.2f | %.1f | %.0f |\n", to_string(narrowphase),
                drift, r.late_creep, r.jitter, 100.0 * r.max_penetration, 100.0 * r.lowest_above_ground, r.asleep,
                r.bodies, r.points_per_manifold, r.manifolds_per_step, r.median_step_us);
  }
  return 0;
}
