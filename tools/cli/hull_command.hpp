// `hedra hull INPUT [--json] [--repeat N] [--out hull.obj] [--triangulate]`:
// the convex hull of a point file (.xyz, .obj, .off), as specified in
// scene-format.md ("Hull").
#pragma once

#include "cli/command.hpp"

namespace hedra::tool {

Subcommand add_hull_command(CLI::App& app);

}  // namespace hedra::tool
