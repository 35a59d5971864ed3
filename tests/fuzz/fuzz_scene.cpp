// Fuzz target: the scene parser and runner of the `hedra` tool (the scene
// library, tools/scene/).
//
// The bytes are the scene file's text. Checked: parse_scene never throws
// and either gives a scene or a message that names the file; a parsed scene
// either builds its shapes or says why (naming the file); every query of a
// built scene runs (at most 8, so one input stays fast) and every number it
// reports is finite (a continuous query's fraction too, and >= 0, and its
// default fraction tolerance is a number >= 0). Mesh files resolve relative to a directory that holds
// none, so a "file" shape exercises the unreadable-file path.
#include <cmath>
#include <cstdint>
#include <string>

#include "fuzz_input.hpp"
#include "scene/scene.hpp"
#include "scene/scene_runner.hpp"

namespace {

bool finite_opt(const std::optional<double>& x) { return !x || std::isfinite(*x); }
bool finite_opt(const std::optional<Eigen::Vector3d>& v) { return !v || v->allFinite(); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string file = "/nonexistent-hedra-fuzz/scene.json";
  hedra::tool::LoadSceneResult loaded;
  try {
    loaded = hedra::tool::parse_scene(text, file);
  } catch (...) {
    HEDRA_FUZZ_CHECK(false, "parse_scene threw");
  }
  if (!loaded.ok()) {
    HEDRA_FUZZ_CHECK(loaded.error.rfind(file, 0) == 0, "message does not name the file: %s", loaded.error.c_str());
    return 0;
  }
  const hedra::tool::Scene& scene = *loaded.scene;
  hedra::tool::BuildShapesResult built;
  try {
    built = hedra::tool::build_shapes(scene);
  } catch (...) {
    HEDRA_FUZZ_CHECK(false, "build_shapes threw");
  }
  if (!built.ok()) {
    HEDRA_FUZZ_CHECK(built.error.rfind(file, 0) == 0, "message does not name the file: %s", built.error.c_str());
    return 0;
  }
  for (std::size_t q = 0; q < scene.queries.size() && q < 8; ++q) {
    const hedra::tool::QueryOutcome out = hedra::tool::run_query(*built.built, q);
    HEDRA_FUZZ_CHECK(finite_opt(out.distance) && finite_opt(out.normal) && finite_opt(out.point_a) &&
                         finite_opt(out.point_b) && std::isfinite(out.error_bound),
                     "query %zu: a non-finite number (status %s)", q, out.status.c_str());
    HEDRA_FUZZ_CHECK(std::isfinite(out.fraction) && out.fraction >= 0.0 && finite_opt(out.point),
                     "query %zu: a non-finite or negative fraction or point (status %s)", q, out.status.c_str());
    if (hedra::tool::is_continuous(scene.queries[q].type)) {
      const double tolerance = hedra::tool::default_fraction_tolerance(*built.built, q);
      HEDRA_FUZZ_CHECK(tolerance >= 0.0 && !std::isnan(tolerance), "query %zu: fraction tolerance %g", q, tolerance);
    }
    for (const auto& c : out.contacts)
      HEDRA_FUZZ_CHECK(c.point.allFinite() && std::isfinite(c.depth), "query %zu: non-finite contact", q);
  }
  return 0;
}
