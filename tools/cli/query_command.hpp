// `hedra query SCENE [--json] [--repeat N] [--stats]`: runs a scene's
// queries and prints the answers, as a table for a person or as the result
// document of scene-format.md.
#pragma once

#include "cli/command.hpp"

namespace hedra::tool {

Subcommand add_query_command(CLI::App& app);

}  // namespace hedra::tool
