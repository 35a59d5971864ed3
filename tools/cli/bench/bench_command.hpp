// `hedra bench`: error against run time beside the peers (bench.hpp).
#pragma once

#include "cli/command.hpp"

namespace hedra::tool {

Subcommand add_bench_command(CLI::App& app);

}  // namespace hedra::tool
