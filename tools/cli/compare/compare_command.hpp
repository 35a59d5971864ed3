// `hedra compare SCENE [--json]`: every query of a scene by hedra and by the
// peers (libccd, FCL, Bullet; when built with HEDRA_WITH_PEERS), each judged
// against the exact reference (compare.hpp has the rules).
#pragma once

#include "cli/command.hpp"

namespace hedra::tool {

Subcommand add_compare_command(CLI::App& app);

}  // namespace hedra::tool
