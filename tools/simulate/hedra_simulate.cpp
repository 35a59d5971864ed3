// hedra_simulate: the reference example of embedding hedra in a simulator.
// Runs one of the scenes of scenes.hpp in Bullet's btDiscreteDynamicsWorld
// with hedra's narrowphase, Bullet's own, or both, and prints one table row
// per narrowphase:
//
//   hedra_simulate --scene stack --seconds 10 --narrowphase both
//
// With --runs N (seeds seed .. seed + N - 1, each start perturbed by
// --perturb) or --scene stiff (every stiff and extreme scene) it prints one
// row per scene and narrowphase over the runs: how many stood, the worst top
// drift, late creep, penetration and jitter, the mean points per manifold,
// the median of the runs' median step times, runs with a NaN or an explosion:
//
//   hedra_simulate --scene stiff --runs 5 --perturb 1e-3 --no-sleep
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
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "simulate/projectile.hpp"
#include "simulate/scenes.hpp"

namespace {

using namespace hedra::simulate;

// The worst (or mean, or median) of a scene's runs for one narrowphase.
struct Summary {
  int runs = 0, stands = 0, non_finite = 0, exploded = 0, failures = 0;
  bool built = false;
  double top_drift = 0.0, late_creep = 0.0, penetration = 0.0, jitter = 0.0, points = 0.0;
  std::vector<double> step_us;
};

Summary summarise(SceneSettings settings, int runs) {
  Summary s;
  const unsigned first = settings.seed;
  for (int k = 0; k < runs; ++k) {
    settings.seed = first + static_cast<unsigned>(k);
    const SceneReport r = run_scene(settings);
    ++s.runs;
    s.built = r.built;
    s.stands += r.stands ? 1 : 0;
    s.non_finite += r.non_finite ? 1 : 0;
    s.exploded += r.exploded ? 1 : 0;
    s.failures += r.measure_failures;
    if (r.top_size > 0.0) s.top_drift = std::max(s.top_drift, r.top_drift / r.top_size);
    s.late_creep = std::max(s.late_creep, r.late_creep / r.size);
    s.penetration = std::max(s.penetration, r.max_penetration);
    s.jitter = std::max(s.jitter, r.jitter);
    s.points += r.points_per_manifold / runs;
    s.step_us.push_back(r.median_step_us);
  }
  return s;
}

void print_summary_header() {
  std::printf(
      "| scene | narrowphase | stands | top drift %% size | late creep %% size | max penetration %% size | jitter m/s "
      "| points / manifold | median step us | NaN / exploded |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
}

void print_summary(SceneKind scene, Narrowphase narrowphase, Summary& s) {
  std::sort(s.step_us.begin(), s.step_us.end());
  char stands[32] = "-", drift[32] = "-";
  if (s.built) {
    std::snprintf(stands, sizeof stands, "%d / %d", s.stands, s.runs);
    std::snprintf(drift, sizeof drift, "%.3f", 100.0 * s.top_drift);
  }
  std::printf("| %s | %s | %s | %s | %.3f | %.3f | %.2e | %.2f | %.0f | %d / %d |\n", to_string(scene),
              to_string(narrowphase), stands, drift, 100.0 * s.late_creep, 100.0 * s.penetration, s.jitter, s.points,
              s.step_us[s.step_us.size() / 2], s.non_finite, s.exploded);
  if (s.failures > 0)
    std::fprintf(stderr, "hedra_simulate: the exact reference failed on %d pairs of %s (left out)\n", s.failures,
                 to_string(scene));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Run a scene in Bullet's btDiscreteDynamicsWorld with hedra's and/or Bullet's narrowphase"};
  std::string scene_name = "stack";
  std::string narrowphase_name = "both";
  SceneSettings settings;
  bool no_sleep = false;
  bool no_anchors = false;
  int runs = 1;
  app.add_option("--scene", scene_name, "a scene of scenes.hpp, stiff (all the stiff and extreme ones) or projectile")
      ->capture_default_str();
  app.add_option("--runs", runs, "runs per scene, seeds seed, seed + 1, ...: one summary row")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  app.add_option("--perturb", settings.perturbation, "start perturbation (fraction of size, rad)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.1));
  app.add_option("--seconds", settings.seconds, "simulated time")->capture_default_str()->check(CLI::Range(0.0, 1e5));
  app.add_option("--hz", settings.hz, "fixed step rate")->capture_default_str()->check(CLI::Range(1.0, 1e5));
  app.add_option("--narrowphase", narrowphase_name, "hedra | bullet | both")->capture_default_str();
  app.add_option("--seed", settings.seed, "seed of the piles' hulls and of the perturbation")->capture_default_str();
  app.add_option("--iterations", settings.solver_iterations, "solver iterations")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000));
  app.add_flag("--no-sleep", no_sleep, "keep every body awake (Bullet's deactivation off)");
  app.add_flag("--no-anchors", no_anchors, "no friction anchors");
  app.add_flag("--bullet-merge", settings.bullet_merge,
               "hedra's points merged one by one by Bullet's btManifoldResult (not keep_new)");
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
  std::vector<SceneKind> scenes = stiff_scenes();
  if (scene_name != "stiff") {
    if (!parse(scene_name, settings.scene)) {
      std::fprintf(stderr, "hedra_simulate: --scene: unknown scene '%s' (see scenes.hpp)\n", scene_name.c_str());
      return 2;
    }
    scenes = {settings.scene};
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

  std::printf(
      "scene %s, %.3g s at %.3g Hz, %d solver iterations, sleeping %s, friction anchors %s, perturbation %.3g, seed "
      "%u, %d run(s)\n\n",
      scene_name.c_str(), settings.seconds, settings.hz, settings.solver_iterations, settings.sleeping ? "on" : "off",
      settings.anchors ? "on" : "off", settings.perturbation, settings.seed, runs);
  if (runs > 1 || scene_name == "stiff") {
    print_summary_header();
    for (const SceneKind scene : scenes)
      for (const Narrowphase narrowphase : narrowphases) {
        settings.scene = scene;
        settings.narrowphase = narrowphase;
        Summary s = summarise(settings, runs);
        print_summary(scene, narrowphase, s);
        std::fflush(stdout);
      }
    return 0;
  }
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
    if (r.built) std::snprintf(drift, sizeof drift, "%.2e (%.2f)", r.top_drift, 100.0 * r.top_drift / r.top_size);
    std::printf("| %s | %s | %.2e | %.2e | %.3f | %.3f | %d / %d | %.2f | %.1f | %.0f |\n", to_string(narrowphase),
                drift, r.late_creep, r.jitter, 100.0 * r.max_penetration, 100.0 * r.lowest_above_ground, r.asleep,
                r.bodies, r.points_per_manifold, r.manifolds_per_step, r.median_step_us);
  }
  return 0;
}
