// `hedra query`: reads a scene (scene.hpp: all validation), builds the
// shapes its queries use, runs each query N times (scene_runner.hpp) and
// prints the answers: a table, or with --json the result document of
// scene-format.md. With --stats it adds what ran (GJK and EPA iterations,
// whether EPA and a manifold ran) per query and what was built per scene; in
// JSON these are optional "stats" fields, which the contract allows.
//
// Fields a query type does not define are JSON null (the distance and
// normal of an intersect query; the normal and closest points of a distance
// query between overlapping shapes); nothing is ever NaN. The continuous
// queries (raycast, cast, toi) have records of their own (continuous_json):
// their vector fields are zero, not null, when there is no hit.
//
// A query over all pairs ("pairs": "all") gives one record per answered pair
// (scene_runner.hpp, run_all_pairs), in (a, b) order, on --threads threads
// (default 0: all cores; the records are the same for any count).
#include "cli/query_command.hpp"

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "cli/cli_validators.hpp"
#include "cli/progress.hpp"
#include "scene/scene_runner.hpp"
#include "scene/timing.hpp"

namespace hedra::tool {

namespace {

struct QueryOptions {
  std::string scene;
  bool json = false;
  int repeat = 1;  // the scene format's default (one warm, timed call)
  bool stats = false;
  int threads = 0;  // 0: all cores
};

constexpr int kMaxThreads = 1024;

// One result record: query `query`'s answer (one of many for all pairs).
struct Record {
  std::size_t query = 0;
  QueryOutcome outcome;
};
// What an all-pairs query did (for --stats).
struct AllPairsStats {
  std::size_t query = 0;
  std::size_t bodies = 0, candidates = 0, pairs = 0;
  double time_ns = 0.0;
};

constexpr int kMaxRepeat = 1000000;

nlohmann::ordered_json vector_json(const std::optional<Eigen::Vector3d>& v) {
  if (!v) return nullptr;
  return {(*v)[0], (*v)[1], (*v)[2]};
}

// A continuous query's record (scene-format.md): raycast answers hit,
// fraction, point and normal; cast and toi hit, fraction, distance, normal,
// point_a, point_b and initially_overlapping. Vector fields are zero, never
// null, when there is no hit.
nlohmann::ordered_json continuous_json(const Scene& scene, const QuerySpec& q, const QueryOutcome& o, bool stats) {
  nlohmann::ordered_json r;
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  if (q.type == QueryType::raycast) {
    r["body"] = scene.bodies[o.body_a].name;
    r["type"] = to_string(q.type);
    r["hit"] = o.hit;
    r["fraction"] = o.fraction;
    r["point"] = vector_json(o.point.value_or(zero));
    r["normal"] = vector_json(o.normal.value_or(zero));
    r["initially_overlapping"] = o.initially_overlapping;  // the ray started inside
  } else {
    r["a"] = scene.bodies[o.body_a].name;
    r["b"] = scene.bodies[o.body_b].name;
    r["type"] = to_string(q.type);
    r["hit"] = o.hit;
    r["fraction"] = o.fraction;
    r["distance"] = o.distance.value_or(0.0);
    r["normal"] = vector_json(o.normal.value_or(zero));
    r["point_a"] = vector_json(o.point_a.value_or(zero));
    r["point_b"] = vector_json(o.point_b.value_or(zero));
    r["initially_overlapping"] = o.initially_overlapping;
  }
  r["iterations"] = {{"cast", o.cast_iterations}};
  r["status"] = o.status;
  r["time_ns"] = static_cast<long long>(std::llround(o.time_ns));
  if (stats) {
    r["stats"] = {
        {"cast_iterations", o.cast_iterations}, {"support_calls", o.support_calls}, {"error_bound", o.error_bound}};
  }
  return r;
}

std::string format_json(const LoadedScene& loaded, const std::vector<Record>& records,
                        const std::vector<AllPairsStats>& all_pairs, bool stats, int repeat) {
  const Scene& scene = *loaded.scene;
  nlohmann::ordered_json document;
  document["scene"] = scene.name;
  document["timing"] = timing_note(repeat);
  document["timed_calls"] = repeat;
  nlohmann::ordered_json results = nlohmann::ordered_json::array();
  for (const Record& record : records) {
    const QueryOutcome& o = record.outcome;
    const QuerySpec& q = scene.queries[record.query];
    if (is_continuous(q.type)) {
      results.push_back(continuous_json(scene, q, o, stats));
      continue;
    }
    nlohmann::ordered_json r;
    r["a"] = scene.bodies[o.body_a].name;
    r["b"] = scene.bodies[o.body_b].name;
    r["type"] = to_string(q.type);
    r["intersecting"] = o.intersecting;
    r["distance"] = o.distance ? nlohmann::ordered_json(*o.distance) : nlohmann::ordered_json(nullptr);
    r["point_a"] = vector_json(o.point_a);
    r["point_b"] = vector_json(o.point_b);
    r["normal"] = vector_json(o.normal);
    nlohmann::ordered_json contacts = nlohmann::ordered_json::array();
    for (const ContactPoint& c : o.contacts) {
      contacts.push_back({{"point", vector_json(c.point)}, {"depth", c.depth}});
    }
    r["contacts"] = std::move(contacts);
    r["iterations"] = {{"gjk", o.gjk_iterations}, {"epa", o.epa_iterations}};
    r["status"] = o.status;
    r["time_ns"] = static_cast<long long>(std::llround(o.time_ns));
    if (stats) {
      r["stats"] = {
          {"gjk_ran", o.sat_axes == 0},         {"gjk_iterations", o.gjk_iterations}, {"epa_ran", o.epa_ran},
          {"epa_iterations", o.epa_iterations}, {"support_calls", o.support_calls},   {"sat_axes", o.sat_axes},
          {"manifold_ran", o.manifold_ran},     {"error_bound", o.error_bound}};
    }
    results.push_back(std::move(r));
  }
  document["results"] = std::move(results);
  if (stats) {
    const BuiltScene& built = loaded.built;
    document["stats"] = {{"shapes_defined", scene.shapes.size()},
                         {"shapes_built", built.shapes_built},
                         {"hulls_built", built.hulls_built},
                         {"mesh_files_read", built.mesh_files_read},
                         {"bodies", scene.bodies.size()},
                         {"queries", scene.queries.size()},
                         {"build_ns", built.build_ns}};
    nlohmann::ordered_json pairs = nlohmann::ordered_json::array();
    for (const AllPairsStats& a : all_pairs)
      pairs.push_back({{"query", a.query},
                       {"bodies", a.bodies},
                       {"candidates", a.candidates},
                       {"pairs", a.pairs},
                       {"time_ns", a.time_ns}});
    if (!all_pairs.empty()) document["stats"]["all_pairs"] = std::move(pairs);
  }
  return document.dump() + "\n";
}

std::string format_vector(const std::optional<Eigen::Vector3d>& v) {
  if (!v) return "-";
  char text[96];
  std::snprintf(text, sizeof text, "[%.6g, %.6g, %.6g]", (*v)[0], (*v)[1], (*v)[2]);
  return text;
}

std::string format_text(const LoadedScene& loaded, const std::vector<Record>& records,
                        const std::vector<AllPairsStats>& all_pairs, const QueryOptions& options) {
  const Scene& scene = *loaded.scene;
  std::string text = "scene " + scene.name + " (" + scene.file + "): " + std::to_string(scene.queries.size()) +
                     (scene.queries.size() == 1 ? " query" : " queries") + "; " + timing_note(options.repeat) + "\n";
  char line[512];
  // `answer`: overlap or apart for the discrete queries (touching counts as
  // overlap), hit or miss for the continuous ones. A ray is labelled
  // ray-<body> here, in `check` and in `compare` alike.
  std::snprintf(line, sizeof line, "%3s  %-12s %-12s %-11s %-14s %-7s %-28s %-32s %4s %4s %10s\n", "#", "a", "b",
                "type", "status", "answer", "distance", "normal", "gjk", "epa", "time");
  text += line;
  for (const Record& record : records) {
    const std::size_t i = record.query;
    const QueryOutcome& o = record.outcome;
    const QuerySpec& q = scene.queries[i];
    const std::string distance = o.distance ? shortest(*o.distance) : "-";
    if (is_continuous(q.type)) {
      // Continuous: "hit" and the fraction, the cast's distance, its
      // iterations in the gjk column.
      char at[64];
      if (q.type == QueryType::raycast) {
        std::snprintf(at, sizeof at, "t=%.10g", o.fraction);
      } else {
        std::snprintf(at, sizeof at, "t=%.10g d=%.3g", o.fraction, o.distance.value_or(0.0));
      }
      const bool ray = q.type == QueryType::raycast;
      std::snprintf(line, sizeof line, "%3zu  %-12s %-12s %-11s %-14s %-7s %-28s %-32s %4d %4s %10s\n", i,
                    ray ? "ray" : scene.bodies[o.body_a].name.c_str(),
                    scene.bodies[ray ? o.body_a : o.body_b].name.c_str(), to_string(q.type), o.status.c_str(),
                    o.hit ? "hit" : "miss", at, format_vector(o.normal).c_str(), o.cast_iterations, "-",
                    format_time(o.time_ns).c_str());
      text += line;
      continue;
    }
    std::snprintf(line, sizeof line, "%3zu  %-12s %-12s %-11s %-14s %-7s %-28s %-32s %4d %4d %10s\n", i,
                  scene.bodies[o.body_a].name.c_str(), scene.bodies[o.body_b].name.c_str(), to_string(q.type),
                  o.status.c_str(), o.intersecting ? "overlap" : "apart", distance.c_str(),
                  format_vector(o.normal).c_str(), o.gjk_iterations, o.epa_iterations, format_time(o.time_ns).c_str());
    text += line;
  }
  if (options.stats) {
    const BuiltScene& built = loaded.built;
    std::snprintf(line, sizeof line, "stats: %d of %zu shapes built (%d hull%s, %d mesh file%s read) in %s\n",
                  built.shapes_built, scene.shapes.size(), built.hulls_built, built.hulls_built == 1 ? "" : "s",
                  built.mesh_files_read, built.mesh_files_read == 1 ? "" : "s", format_time(built.build_ns).c_str());
    text += line;
    for (const AllPairsStats& a : all_pairs) {
      std::snprintf(line, sizeof line, "  #%zu all pairs: %zu bodies, %zu candidate%s, %zu pair%s in %s\n", a.query,
                    a.bodies, a.candidates, a.candidates == 1 ? "" : "s", a.pairs, a.pairs == 1 ? "" : "s",
                    format_time(a.time_ns).c_str());
      text += line;
    }
    for (const Record& record : records) {
      const std::size_t i = record.query;
      const QueryOutcome& o = record.outcome;
      if (is_continuous(o.type)) {
        std::snprintf(line, sizeof line, "  #%zu %s: %d iteration%s, %d support call%s, error bound %.3g\n", i,
                      to_string(o.type), o.cast_iterations, o.cast_iterations == 1 ? "" : "s", o.support_calls,
                      o.support_calls == 1 ? "" : "s", o.error_bound);
        text += line;
        continue;
      }
      if (o.sat_axes > 0) {  // two overlapping boxes: SAT's depth, no GJK or EPA
        std::snprintf(line, sizeof line, "  #%zu %s: sat %d axes, no gjk, no epa, error bound %.3g\n", i,
                      to_string(o.type), o.sat_axes, o.error_bound);
        text += line;
        continue;
      }
      std::snprintf(line, sizeof line, "  #%zu %s: gjk %d iteration%s, %s, %d support call%s, %s, error bound %.3g\n",
                    i, to_string(o.type), o.gjk_iterations, o.gjk_iterations == 1 ? "" : "s",
                    o.epa_ran ? ("epa " + std::to_string(o.epa_iterations) + " iterations").c_str() : "no epa",
                    o.support_calls, o.support_calls == 1 ? "" : "s", o.manifold_ran ? "manifold" : "no manifold",
                    o.error_bound);
      text += line;
    }
  }
  return text;
}

int run_query_command(const QueryOptions& options, std::string& out, std::ostream& err) {
  Progress progress("hedra query");  // stderr, only for work longer than a couple of seconds
  progress.stage("reading " + options.scene + " and building its shapes");
  std::string error;
  std::optional<LoadedScene> loaded = prepare_scene(options.scene, error);
  if (!loaded) {
    err << error << "\n";
    return kExitBadInput;
  }
  std::vector<Record> records;
  std::vector<AllPairsStats> all_pairs;
  records.reserve(loaded->scene->queries.size());
  progress.stage("running queries", loaded->scene->queries.size());
  for (std::size_t i = 0; i < loaded->scene->queries.size(); ++i) {
    if (loaded->scene->queries[i].all_pairs) {
      AllPairsOutcome pairs = run_all_pairs(loaded->built, i, options.repeat, options.threads);
      all_pairs.push_back({i, pairs.bodies, pairs.candidates, pairs.pairs.size(), pairs.time_ns});
      for (QueryOutcome& o : pairs.pairs) records.push_back({i, std::move(o)});
    } else {
      records.push_back({i, run_query(loaded->built, i, options.repeat)});
    }
    progress.advance();
  }
  progress.stage("formatting the output");
  out = options.json ? format_json(*loaded, records, all_pairs, options.stats, options.repeat)
                     : format_text(*loaded, records, all_pairs, options);
  return kExitOk;
}

}  // namespace

Subcommand add_query_command(CLI::App& app) {
  auto options = std::make_shared<QueryOptions>();
  CLI::App* command = app.add_subcommand("query", "Run the queries of a scene file and print the answers");
  command->add_option("scene", options->scene, "Scene file (JSON, see the README)")->required();
  command->add_flag("--json", options->json, "Print the results as one JSON document");
  command
      ->add_option("--repeat", options->repeat,
                   "Time each query N times after an untimed warm-up call and report the median (default 1)")
      ->check(whole_number_in(1, kMaxRepeat, "repeat count"))
      ->type_name("N");
  command
      ->add_option("--threads", options->threads,
                   "Threads for queries over all pairs (0, the default: all cores); the answers are the same "
                   "for any count")
      ->check(whole_number_in(0, kMaxThreads, "thread count"))
      ->type_name("N");
  command->add_flag("--stats", options->stats,
                    "Also report which stages ran per query and which shapes were built per scene");
  return Subcommand{command,
                    [options](std::string& out, std::ostream& err) { return run_query_command(*options, out, err); }};
}

}  // namespace hedra::tool
