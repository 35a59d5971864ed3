// `hedra check SCENE...`: runs every scene's queries and compares the
// answers with their `expect` blocks; one PASS/FAIL line per query.
#pragma once

#include "cli/command.hpp"

namespace hedra::tool {

Subcommand add_check_command(CLI::App& app);

}  // namespace hedra::tool
