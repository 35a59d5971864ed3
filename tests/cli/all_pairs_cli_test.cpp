// End-to-end tests of queries over all pairs ("pairs": "all",
// docs/scene-format.md) in `hedra query`, `hedra check`, `hedra compare` and
// `hedra view`: names in byte order, results sorted by (a, b), the same
// records for any --threads, pair_count checked, and every bad field an
// exit 2 naming its JSON path.
#include <set>
#include <string>
#include <vector>

#include "cli_fixture.hpp"

namespace {

using namespace hedra::cli_test;
using AllPairsCli = HedraCli;

std::string scene(const std::string& bodies, const std::string& queries) {
  return R"({"hedra_scene": 1, "shapes": {"ball": {"type": "sphere", "radius": 1}, "cube": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
 "bodies": )" +
         bodies + ",\n \"queries\": " + queries + "}\n";
}

// Balls on the x axis whose byte order (B < Z10 < Z9 < a) is not the file's.
const std::string kLine =
    R"({"a": {"shape": "ball", "position": [0, 0, 0]}, "B": {"shape": "ball", "position": [1.5, 0, 0]},
 "Z9": {"shape": "ball", "position": [3, 0, 0]}, "Z10": {"shape": "ball", "position": [10, 0, 0]}})";

// Drops the timings, which differ from run to run.
nlohmann::json without_times(nlohmann::json document) {
  for (nlohmann::json& r : document["results"]) r.erase("time_ns");
  return document;
}

TEST_F(AllPairsCli, PairsAreNamedInByteOrderAndSortedByAThenB) {
  const std::string file = write("line.json", scene(kLine, R"([{"type": "distance", "pairs": "all", "max_distance": 5},
        {"a": "a", "b": "B", "type": "penetration"}, {"type": "penetration", "pairs": "all"}])"));
  const nlohmann::json doc = run_json({"query", file, "--json"});
  const std::vector<std::pair<std::string, std::string>> expected = {{"B", "Z9"}, {"B", "a"}, {"Z10", "Z9"},
                                                                     {"Z9", "a"},  // query 0, distance <= 5
                                                                     {"a", "B"},   // query 1, as written
                                                                     {"B", "Z9"}, {"B", "a"}};  // query 2, overlapping
  ASSERT_EQ(doc["results"].size(), expected.size()) << doc.dump();
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(doc["results"][i]["a"], expected[i].first) << i;
    EXPECT_EQ(doc["results"][i]["b"], expected[i].second) << i;
    EXPECT_EQ(doc["results"][i]["status"], "ok");
  }
  // Z10-Z9: 7 apart, radius 1 each: distance 5 exactly, normal from Z10 toward Z9.
  EXPECT_EQ(doc["results"][2]["distance"].get<double>(), 5.0);
  EXPECT_EQ(doc["results"][2]["normal"], nlohmann::json::parse("[-1.0, 0.0, 0.0]"));
  EXPECT_EQ(doc["results"][5]["distance"].get<double>(), -0.5);
  EXPECT_EQ(doc["results"][5]["type"], "penetration");
}

TEST_F(AllPairsCli, RecordsAreTheSameForAnyThreadCount) {
  std::string bodies = "{";
  for (int i = 0; i < 60; ++i) {
    const double x = 0.9 * (i % 8), y = 0.95 * ((i / 8) % 4), z = 0.97 * (i / 32);
    bodies += (i ? ", " : "") + std::string("\"c") + std::to_string(i) + "\": {\"shape\": \"cube\", \"position\": [" +
              std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) +
              "], \"orientation\": [1, 0.1, 0.05, " + std::to_string(0.01 * i) + "]}";
  }
  bodies += "}";
  const std::string file =
      write("cubes.json", scene(bodies, R"([{"type": "contact", "pairs": "all", "max_distance": 0.01},
     {"type": "penetration", "pairs": "all"}])"));
  const nlohmann::json one = without_times(run_json({"query", file, "--json", "--threads", "1"}));
  EXPECT_GT(one["results"].size(), 100u);
  for (const char* threads : {"2", "3", "0"})
    EXPECT_EQ(without_times(run_json({"query", file, "--json", "--threads", threads})), one) << threads;
  EXPECT_EQ(without_times(run_json({"query", file, "--json"})), one);
  const RunResult text = run({"query", file, "--stats"});
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.out.find("all pairs: 60 bodies"), std::string::npos) << text.out;
}

TEST_F(AllPairsCli, CheckComparesPairCount) {
  const std::string good =
      write("good.json", scene(kLine, R"([{"type": "penetration", "pairs": "all", "expect": {"pair_count": 2}}])"));
  const RunResult pass = run({"check", good});
  EXPECT_EQ(pass.exit_code, 0) << pass.out << pass.err;
  EXPECT_NE(pass.out.find("2 pairs within 0 among 4 bodies (expected 2)"), std::string::npos) << pass.out;
  const std::string bad =
      write("bad.json",
            scene(kLine, R"([{"type": "contact", "pairs": "all", "max_distance": 5, "expect": {"pair_count": 3}}])"));
  const RunResult fail = run({"check", bad});
  EXPECT_EQ(fail.exit_code, 1) << fail.out << fail.err;
  EXPECT_NE(fail.out.find("FAIL"), std::string::npos);
}

TEST_F(AllPairsCli, CompareJudgesEveryAnsweredPair) {
  const std::string file =
      write("cmp.json", scene(kLine, R"([{"type": "distance", "pairs": "all", "max_distance": 5}])"));
  const RunResult r = run({"compare", file, "--no-peers"});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("all 4 queries"), std::string::npos) << r.out;
}

TEST_F(AllPairsCli, BadFieldsNameTheirPath) {
  const struct {
    std::string query, message;
  } cases[] = {
      {R"({"type": "penetration", "pairs": "some"})", R"(queries[0].pairs: expected "all")"},
      {R"({"type": "penetration", "pairs": true})", R"(queries[0].pairs: expected "all")"},
      {R"({"type": "raycast", "pairs": "all"})", "queries[0].type: a 'raycast' query has no all-pairs form"},
      {R"({"type": "toi", "pairs": "all"})", "queries[0].type: a 'toi' query has no all-pairs form"},
      {R"({"type": "distance", "pairs": "all", "a": "a"})", "queries[0].a: a query over all pairs names no bodies"},
      {R"({"type": "distance", "pairs": "all", "max_distance": -1})", "queries[0].max_distance: negative"},
      {R"({"type": "distance", "pairs": "all", "max_distance": "far"})",
       "queries[0].max_distance: expected a number, got a string"},
      {R"({"type": "distance", "pairs": "all", "max_distance": 1e61})", "queries[0].max_distance: too large"},
      {R"({"type": "contact", "pairs": "all", "contact_distance": 0.1})",
       "queries[0].contact_distance: a query over all pairs takes 'max_distance'"},
      {R"({"type": "distance", "pairs": "all", "maxdistance": 1})", "queries[0].maxdistance: unknown key"},
      {R"({"type": "distance", "a": "a", "b": "B", "max_distance": 1})",
       "queries[0].max_distance: only a query over all pairs"},
      {R"({"type": "distance", "pairs": "all", "expect": {"pair_count": -1}})",
       "queries[0].expect.pair_count: expected a whole number >= 0"},
      {R"({"type": "distance", "pairs": "all", "expect": {"pair_count": 1.5}})",
       "queries[0].expect.pair_count: expected a whole number >= 0"},
      {R"({"type": "distance", "pairs": "all", "expect": {"intersecting": true}})",
       "queries[0].expect.intersecting: unknown key"},
      {R"({"type": "distance", "pairs": "all", "expect": {}})", "queries[0].expect: missing required key 'pair_count'"},
      {R"({"type": "distance", "a": "a", "b": "B", "expect": {"pair_count": 1}})",
       "queries[0].expect.pair_count: only a query over all pairs"},
  };
  for (const auto& c : cases) {
    const std::string file = write("bad_all_pairs.json", scene(kLine, "[" + c.query + "]"));
    expect_bad({"query", file}, {file + ": " + c.message});
    expect_bad({"check", file}, {file + ": " + c.message});
  }
  const std::string file = write("ok.json", scene(kLine, R"([{"type": "distance", "pairs": "all"}])"));
  expect_bad({"query", file, "--threads", "-1"}, {"--threads"});
  expect_bad({"query", file, "--threads", "two"}, {"--threads"});
}

// No body, or one: no pair, exit 0.
TEST_F(AllPairsCli, FewerThanTwoBodiesAnswerNoPair) {
  for (const std::string& bodies : {std::string("{}"), std::string(R"({"only": {"shape": "ball"}})")}) {
    const std::string file = write(
        "few.json",
        scene(bodies, R"([{"type": "contact", "pairs": "all", "max_distance": 1, "expect": {"pair_count": 0}}])"));
    const nlohmann::json doc = run_json({"query", file, "--json"});
    EXPECT_TRUE(doc["results"].empty()) << doc.dump();
    EXPECT_EQ(run({"check", file}).exit_code, 0);
  }
}

}  // namespace
