// What every subcommand of the `hedra` tool shares: exit codes and the shape
// of a subcommand.
//
// A subcommand lives in its own file (hull_command.cpp, query_command.cpp,
// check_command.cpp; view/, compare/ and bench/ for the larger ones) and
// exposes one function `add_<name>_command(app)`
// that declares its CLI11 subcommand and options and returns a Subcommand
// whose run() does the work once the command line is parsed. hedra.cpp lists
// those functions in one table, so adding a subcommand is a new file plus
// one line there.
//
// Output contract (docs/scene-format.md): run() writes its result into `out`,
// which main() copies to stdout only when the exit code is ok or
// check_failed; diagnostics go to `err` as "file:line: reason". So bad input
// never leaves anything on stdout, whatever the subcommand wrote before it
// noticed.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace CLI {
class App;
}

namespace hedra::tool {

enum ExitCode : int {
  kExitOk = 0,
  kExitCheckFailed = 1,  // `hedra check`: an expectation was not met
  kExitBadInput = 2,     // bad input or usage; the message names the file and line
  // An internal failure (an exception escaping a subcommand: a bug to
  // report, or memory exhausted). The contract (docs/scene-format.md) has
  // exit codes 0, 1 and 2 only, and programs that drive hedra rely on it:
  // this is 2 too, and main() says "internal error" on stderr.
  kExitInternalError = 2
};

struct Subcommand {
  CLI::App* app = nullptr;  // owned by the parent CLI::App
  std::function<int(std::string& out, std::ostream& err)> run;
};

}  // namespace hedra::tool
