// The `hedra` command-line tool (tools/cli/): parses the command line with
// CLI11 and runs the one subcommand named on it.
//
// Each subcommand lives in its own file and is listed once in kSubcommands
// below (see command.hpp for the contract). Exit codes follow
// docs/scene-format.md: 0 success, 1 a check failed, 2 bad input or usage (a
// message on stderr, nothing on stdout); an internal failure (an exception
// escaping a subcommand) is 2 as well, with "internal error" on stderr
// (kExitInternalError). main() enforces the "nothing on stdout" half: a
// subcommand's output is buffered and printed only when it did not fail.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "cli/bench/bench_command.hpp"
#include "cli/check_command.hpp"
#include "cli/command.hpp"
#include "cli/compare/compare_command.hpp"
#include "cli/hull_command.hpp"
#include "cli/query_command.hpp"
#include "cli/view/view_command.hpp"

#ifndef HEDRA_VERSION
#  define HEDRA_VERSION "unknown"
#endif

namespace {

using AddSubcommand = hedra::tool::Subcommand (*)(CLI::App&);

// One line per subcommand.
constexpr AddSubcommand kSubcommands[] = {
    &hedra::tool::add_hull_command, &hedra::tool::add_query_command,   &hedra::tool::add_check_command,
    &hedra::tool::add_view_command, &hedra::tool::add_compare_command, &hedra::tool::add_bench_command,
};

int run(int argc, char** argv) {
  CLI::App app{"hedra: convex hulls and convex collision queries (GJK, EPA, SAT, contact manifolds)", "hedra"};
  app.set_version_flag("--version", HEDRA_VERSION);
  app.require_subcommand(1);

  std::vector<hedra::tool::Subcommand> subcommands;
  for (AddSubcommand add : kSubcommands) subcommands.push_back(add(app));

  // CLI11 would call an unknown subcommand an "extra argument"; name it.
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    std::string names;
    for (const hedra::tool::Subcommand& subcommand : subcommands) {
      known = known || subcommand.app->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + subcommand.app->get_name();
    }
    if (!known) {
      std::cerr << "hedra: unknown subcommand '" << argv[1] << "' (available: " << names
                << ")\nRun 'hedra --help' for usage.\n";
      return hedra::tool::kExitBadInput;
    }
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help, std::cout, std::cerr);  // prints help on stdout, returns 0
  } catch (const CLI::CallForAllHelp& help) {
    return app.exit(help, std::cout, std::cerr);
  } catch (const CLI::CallForVersion& version) {
    return app.exit(version, std::cout, std::cerr);
  } catch (const CLI::ParseError& error) {
    std::cerr << "hedra: " << error.what() << "\nRun 'hedra --help' for usage.\n";
    return hedra::tool::kExitBadInput;
  }

  for (const hedra::tool::Subcommand& subcommand : subcommands) {
    if (!subcommand.app->parsed()) continue;
    std::string out;
    const int code = subcommand.run(out, std::cerr);
    if (code == hedra::tool::kExitOk || code == hedra::tool::kExitCheckFailed) {
      std::cout << out << std::flush;
      if (!std::cout) {
        std::cerr << "hedra: cannot write to standard output\n";
        return hedra::tool::kExitBadInput;
      }
    }
    return code;
  }
  std::cerr << "hedra: no subcommand given\nRun 'hedra --help' for usage.\n";
  return hedra::tool::kExitBadInput;
}

}  // namespace

int main(int argc, char** argv) {
  // Last line of defence: libraries report bad input as values, but an
  // allocation failure or a bug must still end with a message, not a
  // terminate() core dump, and never with partial stdout (it is buffered).
  try {
    return run(argc, argv);
  } catch (const std::exception& error) {
    std::cerr << "hedra: internal error: " << error.what() << "\n";
  } catch (...) {
    std::cerr << "hedra: internal error: unknown exception\n";
  }
  return hedra::tool::kExitInternalError;
}
