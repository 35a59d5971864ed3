// `hedra check SCENE...`: the regression runner. Every scene is read and
// built first (any bad file: exit 2, nothing on stdout); then each query
// runs once and is compared with its `expect`:
//   status         must be "ok" (a query without `expect` must just be ok);
//   intersecting   equal;
//   distance       |value - expected| <= tolerance, the tolerance given or
//                  default_tolerance() (1e-9 of the pair's size, scene.hpp);
//   normal         angle between the unit vectors <= angle_tolerance, given
//                  or kDefaultAngleTolerance (1e-6 rad); a normal that the
//                  query leaves undefined (overlapping shapes in a distance
//                  query) fails;
//   contact_count  equal;
//   hit            equal (raycast, cast, toi);
//   fraction       |value - expected| <= tolerance, the tolerance given or
//                  default_fraction_tolerance() (1e-9 of the size measured
//                  along the motion, scene.hpp).
// One line per query:
//   PASS scenes/demo.json [0] floor-crate penetration: distance -0.1
//        (expected -0.1, error 0 <= 2.2e-09); normal [0, 0, 1] (...)
// then a summary line. Exit 0 when every query passes, 1 otherwise.
#include "cli/check_command.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/progress.hpp"
#include "scene/scene_runner.hpp"

namespace hedra::tool {

namespace {

struct CheckOptions {
  std::vector<std::string> scenes;
};

std::string format_vector(const Eigen::Vector3d& v) {
  return "[" + shortest(v[0]) + ", " + shortest(v[1]) + ", " + shortest(v[2]) + "]";
}

std::string format_error(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2g", x);
  return text;
}

// Compares one outcome with its expectation; appends the findings to
// `detail` and returns whether everything matched.
bool compare(const QueryOutcome& o, const Expectation& e, double default_distance_tolerance,
             double default_fraction_tolerance, std::string& detail) {
  bool pass = true;
  auto add = [&](const std::string& item) { detail += (detail.empty() ? "" : "; ") + item; };
  if (e.intersecting) {
    const bool same = o.intersecting == *e.intersecting;
    pass = pass && same;
    add(std::string("intersecting ") + (o.intersecting ? "true" : "false") + " (expected " +
        (*e.intersecting ? "true" : "false") + ")");
  }
  if (e.distance) {
    const double tolerance = e.tolerance.value_or(default_distance_tolerance);
    if (!o.distance) {
      pass = false;
      add("distance undefined (expected " + shortest(*e.distance) + ")");
    } else {
      const double error = std::abs(*o.distance - *e.distance);
      const bool within = error <= tolerance;  // false for NaN
      pass = pass && within;
      add("distance " + shortest(*o.distance) + " (expected " + shortest(*e.distance) + ", error " +
          format_error(error) + (within ? " <= " : " > ") + format_error(tolerance) + ")");
    }
  }
  if (e.normal) {
    const double tolerance = e.angle_tolerance.value_or(kDefaultAngleTolerance);
    if (!o.normal) {
      pass = false;
      add("normal undefined (expected " + format_vector(*e.normal) + ")");
    } else {
      // atan2 of |cross| and dot: accurate for small and large angles alike.
      const Eigen::Vector3d n = o.normal->normalized();
      const double angle = std::atan2(n.cross(*e.normal).norm(), n.dot(*e.normal));
      const bool within = angle <= tolerance;
      pass = pass && within;
      add("normal " + format_vector(*o.normal) + " (expected " + format_vector(*e.normal) + ", angle " +
          format_error(angle) + (within ? " <= " : " > ") + format_error(tolerance) + " rad)");
    }
  }
  if (e.hit) {
    const bool same = o.hit == *e.hit;
    pass = pass && same;
    add(std::string("hit ") + (o.hit ? "true" : "false") + " (expected " + (*e.hit ? "true" : "false") + ")");
  }
  if (e.fraction) {
    const double tolerance = e.tolerance.value_or(default_fraction_tolerance);
    const double error = std::abs(o.fraction - *e.fraction);
    const bool within = error <= tolerance;  // false for NaN
    pass = pass && within;
    add("fraction " + shortest(o.fraction) + " (expected " + shortest(*e.fraction) + ", error " + format_error(error) +
        (within ? " <= " : " > ") + format_error(tolerance) + ")");
  }
  if (e.contact_count) {
    const int count = static_cast<int>(o.contacts.size());
    pass = pass && count == *e.contact_count;
    add("contact_count " + std::to_string(count) + " (expected " + std::to_string(*e.contact_count) + ")");
  }
  return pass;
}

// A query over all pairs passes when every answered pair's status is ok and
// the count of pairs is `pair_count` (when expected); one line.
bool check_all_pairs(const LoadedScene& loaded, std::size_t index, std::string& out) {
  const Scene& scene = *loaded.scene;
  const QuerySpec& q = scene.queries[index];
  const AllPairsOutcome r = run_all_pairs(loaded.built, index);
  bool pass = true;
  std::string detail = std::to_string(r.pairs.size()) + (r.pairs.size() == 1 ? " pair" : " pairs") + " within " +
                       shortest(q.max_distance) + " among " + std::to_string(r.bodies) + " bodies";
  if (q.expect && q.expect->pair_count) {
    pass = static_cast<long long>(r.pairs.size()) == *q.expect->pair_count;
    detail += " (expected " + std::to_string(*q.expect->pair_count) + ")";
  } else {
    detail += " (no expectation)";
  }
  for (const QueryOutcome& o : r.pairs) {
    if (o.ok()) continue;
    pass = false;
    detail += "; " + scene.bodies[o.body_a].name + "-" + scene.bodies[o.body_b].name + " status " + o.status +
              " (expected ok)";
  }
  out += std::string(pass ? "PASS " : "FAIL ") + scene.file + " [" + std::to_string(index) + "] all pairs " +
         to_string(q.type) + ": " + detail + "\n";
  return pass;
}

int run_check(const CheckOptions& options, std::string& out, std::ostream& err) {
  // Everything is read and built before anything runs: a bad file anywhere
  // fails the whole command with nothing on stdout.
  Progress progress("hedra check");  // stderr, only for work longer than a couple of seconds
  std::vector<LoadedScene> scenes;
  for (const std::string& path : options.scenes) {
    progress.stage("reading " + path + " and building its shapes");
    std::string error;
    std::optional<LoadedScene> loaded = prepare_scene(path, error);
    if (!loaded) {
      err << error << "\n";
      return kExitBadInput;
    }
    scenes.push_back(std::move(*loaded));
  }

  int passed = 0;
  int failed = 0;
  std::size_t query_count = 0;
  for (const LoadedScene& loaded : scenes) query_count += loaded.scene->queries.size();
  progress.stage("running queries", query_count);
  for (const LoadedScene& loaded : scenes) {
    const Scene& scene = *loaded.scene;
    for (std::size_t i = 0; i < scene.queries.size(); ++i) {
      const QuerySpec& q = scene.queries[i];
      if (q.all_pairs) {
        const bool pass = check_all_pairs(loaded, i, out);
        (pass ? passed : failed) += 1;
        progress.advance();
        continue;
      }
      const QueryOutcome o = run_query(loaded.built, i);
      progress.advance();
      std::string detail;
      bool pass = o.ok();
      if (!o.ok()) detail = "status " + o.status + " (expected ok)";
      if (q.expect) {
        const collision::Shape& a = *loaded.built.shapes[scene.bodies[q.a].shape];
        const collision::Shape& b = *loaded.built.shapes[scene.bodies[q.b].shape];
        const double tolerance = default_tolerance(a, loaded.built.poses[q.a], b, loaded.built.poses[q.b]);
        pass = compare(o, *q.expect, tolerance, default_fraction_tolerance(loaded.built, i), detail) && pass;
      } else if (is_continuous(q.type)) {
        const std::string summary = "status " + o.status + ", hit " + (o.hit ? "true" : "false") + ", fraction " +
                                    shortest(o.fraction) + " (no expectation)";
        detail = o.ok() ? summary : detail;
      } else {
        std::string summary = "status " + o.status;
        if (o.distance) summary += ", distance " + shortest(*o.distance);
        summary += std::string(", intersecting ") + (o.intersecting ? "true" : "false") + " (no expectation)";
        detail = o.ok() ? summary : detail;
      }
      (pass ? passed : failed) += 1;
      out += std::string(pass ? "PASS " : "FAIL ") + scene.file + " [" + std::to_string(i) + "] " +
             (q.type == QueryType::raycast ? "ray-" + scene.bodies[q.a].name
                                           : scene.bodies[q.a].name + "-" + scene.bodies[q.b].name) +
             " " + to_string(q.type) + ": " + detail + "\n";
    }
  }
  out += std::to_string(passed + failed) + (passed + failed == 1 ? " query in " : " queries in ") +
         std::to_string(scenes.size()) + (scenes.size() == 1 ? " scene: " : " scenes: ") + std::to_string(passed) +
         " passed, " + std::to_string(failed) + " failed\n";
  return failed == 0 ? kExitOk : kExitCheckFailed;
}

}  // namespace

Subcommand add_check_command(CLI::App& app) {
  auto options = std::make_shared<CheckOptions>();
  CLI::App* command =
      app.add_subcommand("check", "Run the queries of scene files and compare the answers with their 'expect'");
  command->add_option("scenes", options->scenes, "Scene files (JSON, see the README)")->required();
  return Subcommand{command, [options](std::string& out, std::ostream& err) { return run_check(*options, out, err); }};
}

}  // namespace hedra::tool
