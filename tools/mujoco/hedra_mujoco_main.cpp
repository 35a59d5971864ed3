// hedra_mujoco MODEL.xml [--seconds S] [--narrowphase hedra|mujoco|both] [--multiccd] [--json]
//
// Runs a MuJoCo model with hedra's pair functions (hedra_mujoco.hpp), with
// MuJoCo's own (single-point MPR, or multiccd with --multiccd), or both from
// the same start (the model's first keyframe, or qpos0), and prints per run:
//   narrowphase       hedra, mujoco or mujoco-multiccd
//   steps             mj_step calls (S / timestep)
//   max_drift         largest horizontal (x, y) displacement of a free body from its start, over the run, m
//   max_displacement  the same in 3-D, m
//   max_penetration   the largest depth between touching geoms at the end, by the exact reference, m
//   mean_contacts     contacts per step
//   step_us           median wall time of mj_step, microseconds
//   nan               a non-finite state, or MuJoCo's bad-qacc reset, at any step
// With --json one document {"model": ..., "runs": [...]} on stdout. A model
// MuJoCo cannot load exits 2 with MuJoCo's message on stderr and nothing on
// stdout; MuJoCo's warnings go to stderr.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exact_reference.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mujoco/hedra_mujoco.hpp"
#include "mujoco/measure.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Runs a MuJoCo model with hedra's narrowphase, MuJoCo's own, or both"};
  std::string model_path, narrowphase = "both";
  double seconds = 10.0;
  bool multiccd = false, json = false;
  app.add_option("model", model_path, "MuJoCo XML model")->required();
  app.add_option("--seconds", seconds, "simulated time per run")->check(CLI::PositiveNumber);
  app.add_option("--narrowphase", narrowphase, "hedra, mujoco or both")
      ->check(CLI::IsMember({"hedra", "mujoco", "both"}));
  app.add_flag("--multiccd", multiccd, "MuJoCo's runs with its multiccd flag");
  app.add_flag("--json", json, "one JSON document on stdout");
  CLI11_PARSE(app, argc, argv);

  hedra::mujoco::route_messages_to_stderr();
  std::string error;
  mjModel* model = hedra::mujoco::load_model(model_path, &error);
  if (model == nullptr) {
    std::fprintf(stderr, "hedra_mujoco: %s: %s\n", model_path.c_str(), error.c_str());
    return 2;
  }
  std::vector<hedra::mujoco::RunResult> runs;
  if (narrowphase != "mujoco") {
    runs.push_back(hedra::mujoco::run(model, hedra::mujoco::Engine::hedra, seconds, &error));
    if (!error.empty()) {
      std::fprintf(stderr, "hedra_mujoco: %s: %s\n", model_path.c_str(), error.c_str());
      mj_deleteModel(model);
      return 2;
    }
  }
  if (narrowphase != "hedra")
    runs.push_back(hedra::mujoco::run(
        model, multiccd ? hedra::mujoco::Engine::mujoco_multiccd : hedra::mujoco::Engine::mujoco, seconds, &error));
  mj_deleteModel(model);

  if (json) {
    nlohmann::ordered_json doc;
    doc["model"] = model_path;
    doc["runs"] = nlohmann::ordered_json::array();
    for (const auto& r : runs)
      doc["runs"].push_back({{"narrowphase", r.narrowphase},
                             {"steps", r.steps},
                             {"max_drift", r.max_drift},
                             {"max_displacement", r.max_displacement},
                             {"max_penetration", r.max_penetration},
                             {"mean_contacts", r.mean_contacts},
                             {"step_us", r.step_us},
                             {"nan", r.nan}});
    std::printf("%s\n", doc.dump(2).c_str());
  } else {
    std::printf("%s\n", model_path.c_str());
    for (const auto& r : runs)
      std::printf(
          "  %-16s steps %d  max_drift %.3g m  max_displacement %.3g m  max_penetration %.3g m  "
          "mean_contacts %.2f  step_us %.1f  nan %s\n",
          r.narrowphase.c_str(), r.steps, r.max_drift, r.max_displacement, r.max_penetration, r.mean_contacts,
          r.step_us, r.nan ? "yes" : "no");
  }
  return 0;
}
