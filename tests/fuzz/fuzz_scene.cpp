// Fuzz target: the scene parser and runner of the `hedra` tool (the scene
// library, tools/scene/).
//
// The bytes are the scene file's text. Checked: parse_scene never throws
// and either gives a scene or a message that names the file; a parsed scene
// either builds its shapes or says why (naming the file); every query of a
// built scene runs (at most 8, so one input stays fast) and every number it
// reports is finite (a continuous query's fraction too, and >= 0, and its
// default fraction tolerance is a number >= 0); a query over all pairs
// ("pairs": "all") answers pairs a < b sorted by (a, b), with finite numbers,
// and the same pairs and numbers on 1 and 2 threads. Mesh files resolve relative to a directory that holds
// none, so a "file" shape exercises the unreadable-file path.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>

#include "fuzz_input.hpp"
#include "scene/scene.hpp"
#include "scene/scene_runner.hpp"

namespace {

bool finite_opt(const std::optional<double>& x) { return !x || std::isfinite(*x); }
bool finite_opt(const std::optional<Eigen::Vector3d>& v) { return !v || v->allFinite(); }

bool same(const std::optional<double>& x, const std::optional<double>& y) {
  return x.has_value() == y.has_value() && (!x || std::memcmp(&*x, &*y, sizeof(double)) == 0);
}
bool same(const std::optional<Eigen::Vector3d>& x, const std::optional<Eigen::Vector3d>& y) {
  return x.has_value() == y.has_value() && (!x || std::memcmp(x->data(), y->data(), 3 * sizeof(double)) == 0);
}

void check_all_pairs(const hedra::tool::BuiltScene& built, std::size_t q) {
  const hedra::tool::AllPairsOutcome one = hedra::tool::run_all_pairs(built, q, 1, 1);
  const hedra::tool::AllPairsOutcome two = hedra::tool::run_all_pairs(built, q, 1, 2);
  HEDRA_FUZZ_CHECK(one.pairs.size() == two.pairs.size(), "query %zu: %zu pairs on 1 thread, %zu on 2", q,
                   one.pairs.size(), two.pairs.size());
  for (std::size_t k = 0; k < one.pairs.size(); ++k) {
    const hedra::tool::QueryOutcome &x = one.pairs[k], &y = two.pairs[k];
    HEDRA_FUZZ_CHECK(x.body_a < x.body_b && x.body_b < built.scene->bodies.size(), "query %zu: pair %zu (%zu, %zu)", q,
                     k, x.body_a, x.body_b);
    HEDRA_FUZZ_CHECK(
        k == 0 || std::make_pair(one.pairs[k - 1].body_a, one.pairs[k - 1].body_b) < std::make_pair(x.body_a, x.body_b),
        "query %zu: pair %zu out of order", q, k);
    HEDRA_FUZZ_CHECK(finite_opt(x.distance) && finite_opt(x.normal) && finite_opt(x.point_a) && finite_opt(x.point_b) &&
                         std::isfinite(x.error_bound),
                     "query %zu: pair %zu: a non-finite number (status %s)", q, k, x.status.c_str());
    HEDRA_FUZZ_CHECK(x.body_a == y.body_a && x.body_b == y.body_b && x.status == y.status &&
                         x.intersecting == y.intersecting && same(x.distance, y.distance) && same(x.normal, y.normal) &&
                         same(x.point_a, y.point_a) && same(x.point_b, y.point_b) &&
                         x.contacts.size() == y.contacts.size(),
                     "query %zu: pair %zu differs between 1 and 2 threads", q, k);
  }
}

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
    if (scene.queries[q].all_pairs) {
      check_all_pairs(*built.built, q);
      continue;
    }
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
