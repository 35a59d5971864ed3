// `hedra compare`: the command line around compare.hpp. The scene is read
// and built exactly as by `hedra query` (prepare_scene: same messages, exit
// 2 with nothing on stdout), then compare_scene runs hedra, the peers and the
// reference, and the report is printed as a table or one JSON document.
#include "cli/compare/compare_command.hpp"

#include <CLI/CLI.hpp>
#include <charconv>
#include <memory>
#include <string>

#include "cli/cli_validators.hpp"
#include "cli/compare/compare.hpp"

namespace hedra::tool {

namespace {

struct CompareCommandOptions {
  std::string scene;
  bool json = false;
  int repeat = kDefaultRepeat;
  double peer_timeout = 5.0;
  bool no_peers = false;
};

constexpr int kMaxRepeat = 100000;

int run_compare(const CompareCommandOptions& options, std::string& out, std::ostream& err) {
  std::string error;
  std::optional<LoadedScene> loaded = prepare_scene(options.scene, error);
  if (!loaded) {
    err << error << "\n";
    return kExitBadInput;
  }
  // Queries over all pairs: each answered pair is judged like a query of its own.
  expand_all_pairs(*loaded->scene, loaded->built);
  CompareOptions compare;
  compare.repeat = options.repeat;
  compare.peer_timeout_seconds = options.peer_timeout;
  compare.with_peers = !options.no_peers;
  const CompareReport report = compare_scene(*loaded, compare);
  out = options.json ? format_compare_json(report) : format_compare_text(report);
  return compare_exit_code(report);
}

}  // namespace

Subcommand add_compare_command(CLI::App& app) {
  auto options = std::make_shared<CompareCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "compare",
      "Run the queries of a scene with hedra and with libccd, FCL and Bullet, and judge every answer against the "
      "exact reference (exit 1 when hedra disagrees with it)");
  command->add_option("scene", options->scene, "Scene file (JSON, see the README)")->required();
  command->add_flag("--json", options->json, "Print the comparison as one JSON document");
  command
      ->add_option(
          "--repeat", options->repeat,
          "Time each method N times per query after an untimed warm-up call and report the median (default 21)")
      ->check(whole_number_in(1, kMaxRepeat, "repeat count"))
      ->type_name("N");
  command
      ->add_option("--peer-timeout", options->peer_timeout,
                   "Seconds a peer call may take before it is reported as a timeout (default 5)")
      ->check(CLI::Range(0.01, 3600.0))
      ->type_name("SECONDS");
  command->add_flag("--no-peers", options->no_peers, "Compare hedra with the exact reference only");
  return Subcommand{command,
                    [options](std::string& out, std::ostream& err) { return run_compare(*options, out, err); }};
}

}  // namespace hedra::tool
