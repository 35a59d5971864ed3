// End-to-end tests of the continuous queries (raycast, cast, toi) in
// `hedra query`, `hedra check` and `hedra compare` (docs/scene-format.md,
// "Continuous queries"): bad motions, rays and expectations get exit 2,
// nothing on stdout and the file and JSON path; the JSON records hold every
// field of their type, never null or NaN, zero vectors on a miss, and equal
// closed forms; check compares hit and fraction; every scene under
// scenes/continuous/ answers as its expectations say.
#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_fixture.hpp"

namespace {

using namespace hedra::cli_test;
using ContinuousCli = HedraCli;

std::string scene(const std::string& shapes, const std::string& bodies, const std::string& queries) {
  return "{\"hedra_scene\": 1,\n \"shapes\": " + shapes + ",\n \"bodies\": " + bodies + ",\n \"queries\": " + queries +
         "}\n";
}

Eigen::Vector3d vec(const nlohmann::json& v) { return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()}; }

// A ball of radius 0.5 moving from the origin to (10, 0, 0), a ball of
// radius 0.5 at (4, 0, 0) (contact at t = 0.3), a unit box at (0, 5, 0).
const std::string kShapes =
    R"({"ball": {"type": "sphere", "radius": 0.5}, "crate": {"type": "box", "half_extents": [1, 1, 1]}})";
const std::string kBodies = R"({"mover": {"shape": "ball", "end_position": [10, 0, 0]},
  "still": {"shape": "ball", "position": [4, 0, 0]},
  "crate": {"shape": "crate", "position": [0, 5, 0]}})";

// Every field of the record's type, finite; vectors of three numbers.
void expect_well_formed(const nlohmann::json& r) {
  const bool ray = r["type"] == "raycast";
  const std::vector<std::string> keys =
      ray ? std::vector<std::string>{"body",
                                     "type",
                                     "hit",
                                     "fraction",
                                     "point",
                                     "normal",
                                     "initially_overlapping",
                                     "iterations",
                                     "status",
                                     "time_ns"}
          : std::vector<std::string>{"a",          "b",      "type",    "hit",     "fraction",
                                     "distance",   "normal", "point_a", "point_b", "initially_overlapping",
                                     "iterations", "status", "time_ns"};
  for (const std::string& key : keys) ASSERT_TRUE(r.contains(key)) << key << " in " << r.dump();
  EXPECT_TRUE(r["hit"].is_boolean());
  EXPECT_TRUE(r["initially_overlapping"].is_boolean());
  ASSERT_TRUE(r["fraction"].is_number()) << r.dump();  // NaN would print as null
  EXPECT_TRUE(std::isfinite(r["fraction"].get<double>()));
  for (const char* key : {"point", "normal", "point_a", "point_b"}) {
    if (!r.contains(key)) continue;
    ASSERT_TRUE(r[key].is_array() && r[key].size() == 3) << key << " in " << r.dump();
    for (const auto& x : r[key]) ASSERT_TRUE(x.is_number()) << key << " in " << r.dump();
    if (!r["hit"].get<bool>()) {
      EXPECT_EQ(vec(r[key]), Eigen::Vector3d::Zero()) << key << ": zero on a miss";
    }
  }
  if (!ray) {
    ASSERT_TRUE(r["distance"].is_number()) << r.dump();
    if (r["hit"].get<bool>() && !r["initially_overlapping"].get<bool>()) {
      EXPECT_NEAR(vec(r["normal"]).norm(), 1.0, 1e-12);
      const Eigen::Vector3d gap = vec(r["point_b"]) - vec(r["point_a"]);
      EXPECT_LE((gap - r["distance"].get<double>() * vec(r["normal"])).norm(), 1e-9) << r.dump();
    }
  }
  EXPECT_TRUE(r["iterations"]["cast"].is_number_integer());
  EXPECT_GE(r["time_ns"].get<double>(), 0.0);
}

// ---- results ----------------------------------------------------------------

TEST_F(ContinuousCli, QueryJsonMatchesClosedForms) {
  const std::string file = write("c.json", scene(kShapes, kBodies,
                                                 R"([{"a": "mover", "b": "still", "type": "cast"},
                {"a": "mover", "b": "still", "type": "toi", "target_distance": 1},
                {"a": "mover", "b": "crate", "type": "cast"},
                {"type": "raycast", "body": "crate", "origin": [0, 0, 0], "direction": [0, 10, 0]},
                {"type": "raycast", "body": "crate", "origin": [5, 0, 0], "direction": [0, 10, 0], "max_fraction": 2},
                {"type": "raycast", "body": "crate", "origin": [0, 5, 0.5], "direction": [1, 0, 0]},
                {"a": "still", "b": "mover", "type": "toi"}])"));
  const nlohmann::json document = run_json({"query", file, "--json"});
  ASSERT_EQ(document["results"].size(), 7u);
  for (const nlohmann::json& r : document["results"]) {
    SCOPED_TRACE(r.dump());
    expect_well_formed(r);
    EXPECT_EQ(r["status"], "ok");
  }
  const nlohmann::json& cast = document["results"][0];
  EXPECT_EQ(cast["hit"], true);
  EXPECT_NEAR(cast["fraction"].get<double>(), 0.3, 1e-12);  // centres 1 apart after 3 of 10
  EXPECT_LE((vec(cast["normal"]) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  EXPECT_LE((vec(cast["point_a"]) - Eigen::Vector3d(3.5, 0, 0)).norm(), 1e-9);
  EXPECT_EQ(cast["initially_overlapping"], false);
  // Target distance 1: contact when the centres are 2 apart, at t = 0.2.
  const nlohmann::json& target = document["results"][1];
  EXPECT_EQ(target["hit"], true);
  EXPECT_NEAR(target["fraction"].get<double>(), 0.2, 1e-9);
  EXPECT_NEAR(target["distance"].get<double>(), 1.0, 1e-8);
  // The mover passes 5 - 1 - 0.5 = 3.5 below the crate: a miss.
  const nlohmann::json& miss = document["results"][2];
  EXPECT_EQ(miss["hit"], false);
  EXPECT_EQ(miss["fraction"].get<double>(), 1.0);
  EXPECT_EQ(miss["distance"].get<double>(), 0.0);
  // The ray reaches the crate's face y = 4 at t = 0.4, normal -y.
  const nlohmann::json& ray = document["results"][3];
  EXPECT_EQ(ray["body"], "crate");
  EXPECT_EQ(ray["hit"], true);
  EXPECT_NEAR(ray["fraction"].get<double>(), 0.4, 1e-12);
  EXPECT_LE((vec(ray["point"]) - Eigen::Vector3d(0, 4, 0)).norm(), 1e-12);
  EXPECT_LE((vec(ray["normal"]) - Eigen::Vector3d(0, -1, 0)).norm(), 1e-12);
  // Beside the crate: a miss answers max_fraction.
  const nlohmann::json& beside = document["results"][4];
  EXPECT_EQ(beside["hit"], false);
  EXPECT_EQ(beside["fraction"].get<double>(), 2.0);
  // From inside: fraction 0.
  const nlohmann::json& inside = document["results"][5];
  EXPECT_EQ(inside["hit"], true);
  EXPECT_EQ(inside["fraction"].get<double>(), 0.0);
  EXPECT_EQ(inside["initially_overlapping"], true);
  // B moving into A from the other side: the same contact, normal -x.
  const nlohmann::json& reversed = document["results"][6];
  EXPECT_NEAR(reversed["fraction"].get<double>(), 0.3, 1e-9);
  EXPECT_LE((vec(reversed["normal"]) - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-9);
}

TEST_F(ContinuousCli, OverlappingAtTheStartAnswersPenetration) {
  const std::string file =
      write("o.json", scene(kShapes, R"({"p": {"shape": "ball"}, "q": {"shape": "ball", "position": [0.8, 0, 0],
                                         "end_position": [5, 0, 0]}})",
                            R"([{"a": "p", "b": "q", "type": "cast"}, {"a": "p", "b": "q", "type": "toi"}])"));
  const nlohmann::json document = run_json({"query", file, "--json"});
  for (const nlohmann::json& r : document["results"]) {
    SCOPED_TRACE(r.dump());
    expect_well_formed(r);
    EXPECT_EQ(r["hit"], true);
    EXPECT_EQ(r["fraction"].get<double>(), 0.0);
    EXPECT_EQ(r["initially_overlapping"], true);
    EXPECT_NEAR(r["distance"].get<double>(), -0.2, 1e-12);
    EXPECT_LE((vec(r["normal"]) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  }
}

TEST_F(ContinuousCli, StatsAndTable) {
  const std::string file = write("s.json", scene(kShapes, kBodies,
                                                 R"([{"a": "mover", "b": "still", "type": "toi"},
                                {"type": "raycast", "body": "crate", "origin": [0, 0, 0], "direction": [0, 10, 0]}])"));
  const nlohmann::json document = run_json({"query", file, "--json", "--stats", "--repeat", "3"});
  const nlohmann::json& toi = document["results"][0];
  ASSERT_TRUE(toi.contains("stats")) << toi.dump();
  EXPECT_GE(toi["stats"]["cast_iterations"].get<int>(), 1);
  EXPECT_GT(toi["stats"]["support_calls"].get<int>(), 0);
  EXPECT_GE(toi["stats"]["error_bound"].get<double>(), 0.0);
  EXPECT_EQ(toi["stats"]["cast_iterations"], toi["iterations"]["cast"]);
  const RunResult table = run({"query", file});
  EXPECT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("toi"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("t=0.3"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("  ray          crate "), std::string::npos)
      << table.out;  // ray-crate, as check and compare
}

// Every committed continuous scene: well-formed records that meet the
// scene's own expectations (hedra check judges them too, one ctest each).
TEST_F(ContinuousCli, RepositoryScenesAnswerTheirExpectations) {
  int scenes = 0, queries = 0;
  for (const auto& entry : std::filesystem::directory_iterator(HEDRA_SOURCE_DIR "/scenes/continuous")) {
    if (entry.path().extension() != ".json") continue;
    ++scenes;
    const std::string path = entry.path().string();
    const nlohmann::json file = nlohmann::json::parse(slurp(entry.path()));
    const nlohmann::json document = run_json({"query", path, "--json"});
    ASSERT_EQ(document["results"].size(), file["queries"].size()) << path;
    for (std::size_t i = 0; i < file["queries"].size(); ++i) {
      const nlohmann::json& r = document["results"][i];
      const nlohmann::json& expect = file["queries"][i]["expect"];
      SCOPED_TRACE(path + " [" + std::to_string(i) + "] " + r.dump());
      expect_well_formed(r);
      EXPECT_EQ(r["status"], "ok");
      EXPECT_EQ(r["hit"], expect["hit"]);
      EXPECT_LE(std::abs(r["fraction"].get<double>() - expect["fraction"].get<double>()),
                expect["tolerance"].get<double>());
      ++queries;
    }
    const RunResult check = run({"check", path});
    EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
  }
  EXPECT_GE(scenes, 10);
  EXPECT_GE(queries, 40);
}

// ---- check ------------------------------------------------------------------

TEST_F(ContinuousCli, CheckComparesHitAndFraction) {
  const std::string good = write(
      "good.json", scene(kShapes, kBodies,
                         R"([{"a": "mover", "b": "still", "type": "cast", "expect": {"hit": true, "fraction": 0.3}},
                             {"type": "raycast", "body": "crate", "origin": [0, 0, 0], "direction": [0, 10, 0],
                              "expect": {"fraction": 0.4}},
                             {"a": "mover", "b": "crate", "type": "toi", "expect": {"hit": false}},
                             {"a": "mover", "b": "still", "type": "toi"}])"));
  const RunResult pass = run({"check", good});
  EXPECT_EQ(pass.exit_code, 0) << pass.out << pass.err;
  EXPECT_EQ(count_lines(pass.out, "PASS " + good + " [0] mover-still cast: hit true (expected true); fraction 0.3"), 1)
      << pass.out;
  EXPECT_EQ(count_lines(pass.out, "PASS " + good + " [1] ray-crate raycast: fraction 0.4"), 1) << pass.out;
  EXPECT_EQ(count_lines(pass.out, "PASS " + good + " [3] mover-still toi: status ok, hit true, fraction 0.3"), 1)
      << pass.out;

  // A fraction off by 1e-6 (the default tolerance is 1e-9 of the pair's size
  // along the motion: 1e-9 * 2.5 / 10), a wrong hit, and the same fraction
  // under an explicit tolerance that covers it.
  const std::string bad =
      write("bad.json", scene(kShapes, kBodies,
                              R"([{"a": "mover", "b": "still", "type": "cast", "expect": {"fraction": 0.300001}},
                {"a": "mover", "b": "crate", "type": "cast", "expect": {"hit": true}},
                {"a": "mover", "b": "still", "type": "toi", "expect": {"fraction": 0.300001, "tolerance": 1e-5}}])"));
  const RunResult fail = run({"check", bad});
  EXPECT_EQ(fail.exit_code, 1) << fail.out << fail.err;
  EXPECT_EQ(count_lines(fail.out, "FAIL " + bad + " [0] mover-still cast: fraction 0.3 (expected 0.300001, error "), 1)
      << fail.out;
  EXPECT_EQ(count_lines(fail.out, "FAIL " + bad + " [1] mover-crate cast: hit false (expected true)"), 1) << fail.out;
  EXPECT_EQ(count_lines(fail.out, "PASS " + bad + " [2]"), 1) << fail.out;
  EXPECT_NE(fail.out.find("3 queries in 1 scene: 1 passed, 2 failed"), std::string::npos) << fail.out;
}

TEST_F(ContinuousCli, CompareJudgesContinuousQueriesAgainstTheFirstContact) {
  const RunResult result = run({"compare", HEDRA_SOURCE_DIR "/scenes/continuous/sphere_sphere.json"});
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  EXPECT_EQ(result.out.find("not compared"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("reference first contact in ["), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("hedra agrees with the exact reference on all"), std::string::npos) << result.out;
}

// ---- bad input: exit 2, stdout empty, file and JSON path named ------------

TEST_F(ContinuousCli, BadMotionsRaysAndExpectations) {
  struct Case {
    std::string bodies_extra;  // appended to body "p"
    std::string query;
    std::string needle;
  };
  const std::vector<Case> cases = {
      {"", R"({"type": "raycast", "body": "p", "origin": [0, 0, 0], "direction": [0, 0, 0]})",
       "queries[0].direction: zero vector"},
      {"", R"({"type": "raycast", "body": "p", "origin": [0, 0, 0], "direction": [1, 0, 0], "max_fraction": -1})",
       "queries[0].max_fraction: negative"},
      {"", R"({"type": "raycast", "body": "p", "origin": [0, 0], "direction": [1, 0, 0]})",
       "queries[0].origin: expected 3 numbers"},
      {"", R"({"type": "raycast", "body": "p", "direction": [1, 0, 0]})", "queries[0]: missing required key 'origin'"},
      {"", R"({"type": "raycast", "body": "z", "origin": [0, 0, 0], "direction": [1, 0, 0]})",
       "queries[0].body: unknown body 'z'"},
      {"", R"({"type": "raycast", "a": "p", "body": "p", "origin": [0, 0, 0], "direction": [1, 0, 0]})",
       "queries[0].a: unknown key"},
      {"", R"({"type": "cast", "a": "p", "b": "q", "target_distance": -0.5})", "queries[0].target_distance: negative"},
      {"", R"({"type": "toi", "a": "p", "b": "q", "target_distance": "far"})",
       "queries[0].target_distance: expected a number, got a string"},
      {"", R"({"type": "distance", "a": "p", "b": "q", "target_distance": 1})",
       "queries[0].target_distance: unknown key"},
      {R"(, "end_orientation": [0, 0, 0, 0])", R"({"type": "toi", "a": "p", "b": "q"})",
       "bodies.p.end_orientation: zero quaternion"},
      {R"(, "end_position": [1, 2])", R"({"type": "toi", "a": "p", "b": "q"})",
       "bodies.p.end_position: expected 3 numbers, got 2"},
      {R"(, "end_position": [1e61, 0, 0])", R"({"type": "cast", "a": "p", "b": "q"})",
       "bodies.p.end_position[0]: too far from the origin"},
      {R"(, "end_velocity": [1, 2, 3])", R"({"type": "toi", "a": "p", "b": "q"})",
       "bodies.p.end_velocity: unknown key"},
      {"", R"({"type": "toi", "a": "p", "b": "q", "expect": {"distance": 1}})",
       "queries[0].expect.distance: a 'toi' query expects only 'hit' and 'fraction'"},
      {"", R"({"type": "distance", "a": "p", "b": "q", "expect": {"hit": true}})",
       "queries[0].expect.hit: a 'distance' query has no 'hit'"},
      {"", R"({"type": "penetration", "a": "p", "b": "q", "expect": {"fraction": 0.5}})",
       "queries[0].expect.fraction: a 'penetration' query has no 'fraction'"},
      {"", R"({"type": "cast", "a": "p", "b": "q", "expect": {"hit": 1}})",
       "queries[0].expect.hit: expected true or false"},
      {"", R"({"type": "cast", "a": "p", "b": "q", "expect": {"fraction": -0.1}})",
       "queries[0].expect.fraction: negative"},
      {"", R"({"type": "cast", "a": "p", "b": "q", "expect": {"tolerance": 1e-3}})",
       "queries[0].expect.tolerance: no 'fraction' expected"},
      {"", R"({"type": "cast", "a": "p", "b": "q", "expect": {}})", "queries[0].expect: empty"},
      {"", R"({"type": "sweep", "a": "p", "b": "q"})", "queries[0].type: unknown query type 'sweep'"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    SCOPED_TRACE(c.query);
    const std::string file = write(
        "bad" + std::to_string(i) + ".json",
        scene(kShapes,
              R"({"p": {"shape": "ball")" + c.bodies_extra + R"(}, "q": {"shape": "ball", "position": [3, 0, 0]}})",
              "[" + c.query + "]"));
    expect_bad({"query", file}, {file + ": " + c.needle});
    expect_bad({"check", file}, {file + ": " + c.needle});
  }
  // NaN is not JSON: a malformed file, named with its line and column.
  const std::string nan = write("nan.json", scene(kShapes, R"({"p": {"shape": "ball", "end_position": [0, NaN, 0]}})",
                                                  R"([{"type": "raycast", "body": "p", "origin": [0, 0, 0],
                                                       "direction": [1, 0, 0]}])"));
  expect_bad({"query", nan}, {nan + ":", "malformed JSON"});
}

}  // namespace
