// `hedra view SCENE [-o scene.html]` and `hedra view --hull INPUT [-o
// out.html]`: writes one self-contained HTML page showing a scene (bodies,
// closest points, normals, contacts) or a convex hull (input points, faces,
// half-edges). The tool only writes the file; open it in any browser.
#pragma once

#include <optional>
#include <string>

#include "cli/command.hpp"
#include "cli/view/view_model.hpp"

namespace hedra::tool {

Subcommand add_view_command(CLI::App& app);

namespace view {

// The view of a scene file: every body tessellated in the world frame
// (make_view_body in tessellate.hpp) and every query's result. Returns
// nothing and sets `error` ("file: reason", as the scene parser words it)
// when the scene is bad. Loads, builds and runs the scene with the scene
// library (scene/scene_runner.hpp), as `hedra query` does.
std::optional<ViewModel> build_scene_view_model(const std::string& scene_path, std::string& error);

// The view of the convex hull of the points in `input` (.xyz, .obj, .off).
// Returns nothing and sets `error` when the file cannot be read or the hull
// cannot be built; `exit_code` says which exit code that deserves.
std::optional<ViewModel> build_hull_view_model(const std::string& input, std::string& error, int& exit_code);

}  // namespace view

}  // namespace hedra::tool
