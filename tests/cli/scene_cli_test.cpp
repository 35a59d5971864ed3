// End-to-end tests of `hedra query` and `hedra check` on scene files
// (docs/scene-format.md): every kind of bad input gets exit 2, nothing on
// stdout and a message naming the file and the JSON path (or line and
// column); the JSON results are well-formed and equal closed forms; --repeat
// and --stats report what they promise (an intersect query runs no EPA, a
// scene of spheres builds no hull, a shared hull is built once); check exits
// 0 when the expectations hold and 1 when one does not.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cli_fixture.hpp"

namespace {

using namespace hedra::cli_test;
using SceneCli = HedraCli;

// A scene document with the given sections (raw JSON text).
std::string scene(const std::string& shapes, const std::string& bodies, const std::string& queries) {
  return "{\"hedra_scene\": 1,\n \"shapes\": " + shapes + ",\n \"bodies\": " + bodies + ",\n \"queries\": " + queries +
         "}\n";
}

const std::string kTwoBalls = R"({"ball": {"type": "sphere", "radius": 1}})";
const std::string kTwoBallBodies =
    R"({"p": {"shape": "ball", "position": [0, 0, 0]}, "q": {"shape": "ball", "position": [3, 4, 0]}})";
const std::string kBallQuery = R"([{"a": "p", "b": "q", "type": "distance"}])";

Eigen::Vector3d vec(const nlohmann::json& v) { return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()}; }

// ---- bad input: exit 2, stdout empty, file and JSON path named ------------

TEST_F(SceneCli, MalformedJsonNamesLineAndColumn) {
  const std::string file = write("bad.json", "{\"hedra_scene\": 1,\n  \"shapes\": {\n    \"s\" {}\n}}\n");
  // The '{' where ':' belongs: line 3, column 9.
  expect_bad({"query", file}, {file + ":3:9: malformed JSON: ", "expected ':'"});
  expect_bad({"check", file}, {file + ":3:"});
}

TEST_F(SceneCli, VersionMissingOrUnsupported) {
  const std::string missing = write("missing.json", R"({"shapes": {}, "bodies": {}, "queries": []})");
  expect_bad({"query", missing}, {missing + ": hedra_scene: missing"});
  const std::string future = write("future.json", R"({"hedra_scene": 2, "shapes": {}})");
  expect_bad({"query", future}, {future + ": hedra_scene: unsupported version 2"});
  const std::string text = write("text.json", R"({"hedra_scene": "1"})");
  expect_bad({"query", text}, {text + ": hedra_scene: "});
}

TEST_F(SceneCli, UnknownShapeType) {
  const std::string file =
      write("s.json", scene(R"({"ball": {"type": "spere", "radius": 1}})", kTwoBallBodies, kBallQuery));
  expect_bad({"query", file}, {file + ": shapes.ball.type: unknown shape type 'spere'"});
}

TEST_F(SceneCli, UnknownReferences) {
  const std::string shape =
      write("shape.json", scene(kTwoBalls, R"({"p": {"shape": "bal"}, "q": {"shape": "ball"}})", kBallQuery));
  expect_bad({"query", shape}, {shape + ": bodies.p.shape: unknown shape 'bal'"});
  const std::string body =
      write("body.json", scene(kTwoBalls, kTwoBallBodies, R"([{"a": "p", "b": "r", "type": "distance"}])"));
  expect_bad({"query", body}, {body + ": queries[0].b: unknown body 'r'"});
}

TEST_F(SceneCli, MissingFields) {
  const std::string radius = write("radius.json", scene(R"({"ball": {"type": "sphere"}})", kTwoBallBodies, kBallQuery));
  expect_bad({"query", radius}, {radius + ": shapes.ball: missing required key 'radius'"});
  const std::string shape = write("shape.json", scene(kTwoBalls, R"({"p": {}, "q": {"shape": "ball"}})", kBallQuery));
  expect_bad({"query", shape}, {shape + ": bodies.p: missing required key 'shape'"});
  const std::string type = write("type.json", scene(kTwoBalls, kTwoBallBodies, R"([{"a": "p", "b": "q"}])"));
  expect_bad({"query", type}, {type + ": queries[0]: missing required key 'type'"});
  const std::string queries = write("queries.json", R"({"hedra_scene": 1, "shapes": {}, "bodies": {}})");
  expect_bad({"query", queries}, {queries + ": queries: missing"});
  const std::string points = write("points.json", scene(R"({"rock": {"type": "hull"}})", "{}", "[]"));
  expect_bad({"query", points}, {points + ": shapes.rock: missing required key 'points' or 'file'"});
}

TEST_F(SceneCli, WrongArrayLengths) {
  const std::string points =
      write("points.json",
            scene(R"({"rock": {"type": "hull", "points": [[0,0,0],[1,0,0],[0,1,0],[0,0],[0,0,1]]}})", "{}", "[]"));
  expect_bad({"query", points}, {points + ": shapes.rock.points[3]: expected 3 numbers"});
  const std::string box = write("box.json", scene(R"({"b": {"type": "box", "half_extents": [1, 1]}})", "{}", "[]"));
  expect_bad({"query", box}, {box + ": shapes.b.half_extents: expected 3 numbers"});
  const std::string position = write(
      "position.json",
      scene(kTwoBalls, R"({"p": {"shape": "ball", "position": [0, 0, 0, 0]}, "q": {"shape": "ball"}})", kBallQuery));
  expect_bad({"query", position}, {position + ": bodies.p.position: expected 3 numbers"});
  const std::string orientation = write(
      "orientation.json",
      scene(kTwoBalls, R"({"p": {"shape": "ball", "orientation": [1, 0, 0]}, "q": {"shape": "ball"}})", kBallQuery));
  expect_bad({"query", orientation}, {orientation + ": bodies.p.orientation: expected 4 numbers"});
}

TEST_F(SceneCli, ZeroOrNonFiniteQuaternion) {
  const std::string zero = write(
      "zero.json",
      scene(kTwoBalls, R"({"p": {"shape": "ball", "orientation": [0, 0, 0, 0]}, "q": {"shape": "ball"}})", kBallQuery));
  expect_bad({"query", zero}, {zero + ": bodies.p.orientation: zero quaternion"});
  // JSON has no NaN literal; a number beyond a double is the non-finite
  // value a file can hold, and is located by line and column.
  const std::string huge =
      write("huge.json",
            scene(kTwoBalls, R"({"p": {"shape": "ball", "orientation": [1e999, 0, 0, 0]}, "q": {"shape": "ball"}})",
                  kBallQuery));
  expect_bad({"query", huge}, {huge + ":3:", "1e999"});
  const std::string nan = write(
      "nan.json", scene(kTwoBalls, R"({"p": {"shape": "ball", "orientation": [NaN, 0, 0, 0]}, "q": {"shape": "ball"}})",
                        kBallQuery));
  expect_bad({"query", nan}, {nan + ":3:", "malformed JSON"});
}

TEST_F(SceneCli, NegativeSizes) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"ball": {"type": "sphere", "radius": -1}})", "shapes.ball.radius: negative"},
      {R"({"ball": {"type": "capsule", "radius": 1, "half_length": -0.5}})", "shapes.ball.half_length: negative"},
      {R"({"ball": {"type": "box", "half_extents": [1, -2, 1]}})", "shapes.ball.half_extents[1]: negative"},
      {R"({"ball": {"type": "sphere", "radius": 1, "margin": -0.1}})", "shapes.ball.margin: negative"},
  };
  for (const auto& [shapes, message] : cases) {
    const std::string file = write("neg.json", scene(shapes, kTwoBallBodies, kBallQuery));
    expect_bad({"query", file}, {file + ": " + message});
  }
}

// Sizes and positions beyond 1e60 would overflow the squared distances of a
// query (found by fuzzing the library): rejected where they are written.
TEST_F(SceneCli, SizesAndPositionsOutOfRange) {
  const std::string big = write(
      "big.json", scene(R"({"ball": {"type": "box", "half_extents": [1e300, 1, 1]}})", kTwoBallBodies, kBallQuery));
  expect_bad({"query", big}, {big + ": shapes.ball.half_extents[0]: too large", "at most 1e60"});
  const std::string far = write(
      "far.json",
      scene(kTwoBalls, R"({"p": {"shape": "ball", "position": [0, -1e70, 0]}, "q": {"shape": "ball"}})", kBallQuery));
  expect_bad({"query", far}, {far + ": bodies.p.position[1]: too far from the origin"});
  const std::string wide =
      write("wide.json",
            scene(R"({"ball": {"type": "hull", "points": [[0,0,0],[1e61,0,0],[0,1,0]]}})", kTwoBallBodies, kBallQuery));
  expect_bad({"query", wide}, {wide + ": shapes.ball", "more than 1e60 apart"});
}

// A pair within 1e-60 (sizes and distance; squares underflow) is refused by
// the library's queries (min_pair_extent): bad input for the tool, named by
// its query, not a table of invalid_input with exit code 0. A tiny ball far
// from the other, or two coincident points, are answered.
TEST_F(SceneCli, PairsBelowTheMinimumExtent) {
  const std::string tiny = write(
      "tiny.json", scene(R"({"ball": {"type": "sphere", "radius": 1e-300}, "big": {"type": "sphere", "radius": 1}})",
                         R"({"p": {"shape": "ball"}, "q": {"shape": "ball", "position": [1e-300, 0, 0]},
                "r": {"shape": "big", "position": [5, 0, 0]}})",
                         R"([{"a": "p", "b": "r", "type": "distance"}, {"a": "p", "b": "q", "type": "penetration"}])"));
  expect_bad({"query", tiny}, {tiny + ": queries[1]: bodies 'p' and 'q' fit within 1e-60"});
  const std::string apart =
      write("apart.json", scene(R"({"ball": {"type": "sphere", "radius": 1e-300}})", kTwoBallBodies, kBallQuery));
  EXPECT_NEAR(run_json({"query", apart, "--json"})["results"][0]["distance"].get<double>(), 5.0, 1e-15);
  const std::string points =
      write("points.json", scene(R"({"ball": {"type": "sphere", "radius": 0}})",
                                 R"({"p": {"shape": "ball"}, "q": {"shape": "ball"}})", kBallQuery));
  EXPECT_EQ(run_json({"query", points, "--json"})["results"][0]["status"], "ok");
  // Touching: a signed distance of zero, printed without a sign (-(0 depth)
  // would read as a penetration).
  const std::string touching = write("touching.json", scene(R"({"ball": {"type": "sphere", "radius": 0}})",
                                                            R"({"p": {"shape": "ball"}, "q": {"shape": "ball"}})",
                                                            R"([{"a": "p", "b": "q", "type": "penetration"}])"));
  const auto printed = run({"query", touching, "--json"});
  ASSERT_EQ(printed.exit_code, 0) << printed.err;
  EXPECT_NE(printed.out.find(R"("distance":0.0)"), std::string::npos) << printed.out;
  EXPECT_EQ(printed.out.find("-0.0"), std::string::npos) << printed.out;
}

TEST_F(SceneCli, WrongValueTypes) {
  const std::string file =
      write("t.json", scene(R"({"ball": {"type": "sphere", "radius": "1"}})", kTwoBallBodies, kBallQuery));
  expect_bad({"query", file}, {file + ": shapes.ball.radius: expected a number, got a string"});
  const std::string expect =
      write("e.json", scene(kTwoBalls, kTwoBallBodies,
                            R"([{"a": "p", "b": "q", "type": "distance", "expect": {"intersecting": "no"}}])"));
  expect_bad({"query", expect}, {expect + ": queries[0].expect.intersecting: expected true or false"});
}

TEST_F(SceneCli, UnreadableOrMalformedMesh) {
  const std::string bodies = R"({"p": {"shape": "rock"}, "q": {"shape": "rock", "position": [5, 0, 0]}})";
  const std::string query = R"([{"a": "p", "b": "q", "type": "distance"}])";
  const std::string missing =
      write("missing.json", scene(R"({"rock": {"type": "hull", "file": "no_such.obj"}})", bodies, query));
  expect_bad({"query", missing}, {missing + ": shapes.rock.file: ", "no_such.obj", "cannot open"});
  write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1\n");
  const std::string bad = write("bad.json", scene(R"({"rock": {"type": "hull", "file": "bad.obj"}})", bodies, query));
  expect_bad({"query", bad}, {bad + ": shapes.rock.file: ", "bad.obj:3: expected 3 numbers"});
  write("empty.xyz", "# nothing\n");
  const std::string empty =
      write("empty.json", scene(R"({"rock": {"type": "hull", "file": "empty.xyz"}})", bodies, query));
  expect_bad({"query", empty}, {empty + ": shapes.rock.file: ", "empty.xyz", "no points"});
  const std::string extension =
      write("ext.json", scene(R"({"rock": {"type": "hull", "file": "rock.ply"}})", bodies, query));
  expect_bad({"query", extension}, {extension + ": shapes.rock.file: unknown file extension"});
}

TEST_F(SceneCli, EmptyHull) {
  const std::string file = write("e.json", scene(R"({"rock": {"type": "hull", "points": []}})", "{}", "[]"));
  expect_bad({"query", file}, {file + ": shapes.rock.points: empty"});
  const std::string both =
      write("both.json", scene(R"({"rock": {"type": "hull", "points": [[0,0,0]], "file": "a.obj"}})", "{}", "[]"));
  expect_bad({"query", both}, {both + ": shapes.rock: give either 'points' or 'file'"});
}

TEST_F(SceneCli, UnknownKeysAreErrors) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {scene(R"({"ball": {"type": "sphere", "radius": 1, "margn": 0.1}})", kTwoBallBodies, kBallQuery),
       "shapes.ball.margn: unknown key"},
      {scene(kTwoBalls, R"({"p": {"shape": "ball", "postion": [0,0,0]}, "q": {"shape": "ball"}})", kBallQuery),
       "bodies.p.postion: unknown key"},
      {scene(kTwoBalls, kTwoBallBodies, R"([{"a": "p", "b": "q", "type": "distance", "exepct": {}}])"),
       "queries[0].exepct: unknown key"},
      {scene(kTwoBalls, kTwoBallBodies,
             R"([{"a": "p", "b": "q", "type": "distance", "expect": {"distance": 3, "tolerence": 1}}])"),
       "queries[0].expect.tolerence: unknown key"},
      {R"({"hedra_scene": 1, "shape": {}, "bodies": {}, "queries": []})", "shape: unknown key"},
      {R"({"hedra_scene": 1, "shapes": {"s": {"type": "sphere", "radius": 1, "radius": 2}}, "bodies": {}, "queries": []})",
       "shapes.s.radius: duplicate key"},
  };
  for (const auto& [text, message] : cases) {
    const std::string file = write("u.json", text);
    expect_bad({"query", file}, {file + ": " + message});
  }
  // ... but a top-level name and description are free text.
  const std::string ok =
      write("ok.json", R"({"hedra_scene": 1, "name": "n", "description": "d", "shapes": )" + kTwoBalls +
                           ", \"bodies\": " + kTwoBallBodies + ", \"queries\": " + kBallQuery + "}");
  EXPECT_EQ(run_json({"query", ok, "--json"})["scene"], "n");
}

TEST_F(SceneCli, ExpectationsTheQueryCannotAnswer) {
  const std::string distance = write(
      "d.json",
      scene(kTwoBalls, kTwoBallBodies, R"([{"a": "p", "b": "q", "type": "intersect", "expect": {"distance": 3}}])"));
  expect_bad({"check", distance},
             {distance + ": queries[0].expect.distance: an 'intersect' query computes no distance"});
  const std::string negative = write(
      "n.json",
      scene(kTwoBalls, kTwoBallBodies, R"([{"a": "p", "b": "q", "type": "distance", "expect": {"distance": -1}}])"));
  expect_bad({"check", negative}, {negative + ": queries[0].expect.distance: negative"});
  const std::string count =
      write("c.json", scene(kTwoBalls, kTwoBallBodies,
                            R"([{"a": "p", "b": "q", "type": "penetration", "expect": {"contact_count": 1}}])"));
  expect_bad({"check", count}, {count + ": queries[0].expect.contact_count: "});
  const std::string normal =
      write("z.json", scene(kTwoBalls, kTwoBallBodies,
                            R"([{"a": "p", "b": "q", "type": "distance", "expect": {"normal": [0, 0, 0]}}])"));
  expect_bad({"check", normal}, {normal + ": queries[0].expect.normal: zero vector"});
}

// A box resting 0.01 deep on a larger box: the contact query returns the
// four corners of the top box's bottom face, each 0.01 deep, and the normal
// from A (the ground) up toward B.
TEST_F(SceneCli, ContactReturnsTheFaceManifold) {
  const std::string file = write(
      "contact.json",
      scene(
          R"({"ground": {"type": "box", "half_extents": [2, 2, 0.5]}, "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}})",
          R"({"g": {"shape": "ground"}, "c": {"shape": "crate", "position": [0, 0, 0.99]}})",
          R"([{"a": "g", "b": "c", "type": "contact", "expect": {"contact_count": 4, "distance": -0.01, "normal": [0, 0, 1]}}])"));
  const RunResult query = run({"query", file, "--json"});
  ASSERT_EQ(query.exit_code, 0) << query.err;
  const nlohmann::json doc = nlohmann::json::parse(query.out);
  const nlohmann::json& r = doc["results"][0];
  EXPECT_EQ(r["status"], "ok");
  EXPECT_TRUE(r["intersecting"].get<bool>());
  EXPECT_NEAR(r["distance"].get<double>(), -0.01, 1e-12);
  EXPECT_NEAR(r["normal"][2].get<double>(), 1.0, 1e-12);
  ASSERT_EQ(r["contacts"].size(), 4u);
  for (const nlohmann::json& c : r["contacts"]) {
    EXPECT_NEAR(c["depth"].get<double>(), 0.01, 1e-12);
    EXPECT_NEAR(std::abs(c["point"][0].get<double>()), 0.5, 1e-9);
    EXPECT_NEAR(std::abs(c["point"][1].get<double>()), 0.5, 1e-9);
  }
  const RunResult check = run({"check", file});
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
}

// A contact query's --stats carry the manifold's certified error bound
// (ContactResult::error_bound, as a penetration query's): the exact depth 0.01
// of a crate resting in a ground box lies within it, and it is rounding small;
// a pair apart beyond the contact distance reports penetration()'s distance
// and bound.
TEST_F(SceneCli, ContactReportsItsErrorBound) {
  const std::string file = write(
      "contact_bound.json",
      scene(
          R"({"ground": {"type": "box", "half_extents": [2, 2, 0.5]}, "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}})",
          R"({"g": {"shape": "ground"}, "c": {"shape": "crate", "position": [0.3, 0, 0.99]}, "far": {"shape": "crate", "position": [0, 0, 3]}})",
          R"([{"a": "g", "b": "c", "type": "contact"}, {"a": "g", "b": "far", "type": "contact"}])"));
  const nlohmann::json document = run_json({"query", file, "--json", "--stats"});
  const nlohmann::json& resting = document["results"][0];
  ASSERT_TRUE(resting.contains("stats")) << resting.dump();
  const double bound = resting["stats"]["error_bound"].get<double>();
  EXPECT_GE(bound, 0.0);
  EXPECT_LT(bound, 1e-12);
  EXPECT_LE(std::abs(resting["distance"].get<double>() + 0.01), bound + 1e-15);
  const nlohmann::json& apart = document["results"][1];
  EXPECT_NEAR(apart["distance"].get<double>(), 2.0, apart["stats"]["error_bound"].get<double>() + 1e-12);
  EXPECT_LT(apart["stats"]["error_bound"].get<double>(), 1e-9);
}

// A box 0.01 above a larger box: with "contact_distance": 0.02 the contact
// query returns the four corners as speculative points (depth -0.01, not
// intersecting); without it, no points (the format's default, 0).
TEST_F(SceneCli, ContactDistanceGivesSpeculativePoints) {
  const std::string shapes =
      R"({"ground": {"type": "box", "half_extents": [2, 2, 0.5]}, "crate": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}})";
  const std::string bodies = R"({"g": {"shape": "ground"}, "c": {"shape": "crate", "position": [0, 0, 1.01]}})";
  const std::string file = write(
      "speculative.json",
      scene(
          shapes, bodies,
          R"([{"a": "g", "b": "c", "type": "contact", "contact_distance": 0.02, "expect": {"contact_count": 4, "intersecting": false, "distance": 0.01}},
                {"a": "g", "b": "c", "type": "contact", "expect": {"contact_count": 0, "distance": 0.01}},
                {"a": "g", "b": "c", "type": "contact", "contact_distance": 0.005, "expect": {"contact_count": 0}}])"));
  const RunResult query = run({"query", file, "--json"});
  ASSERT_EQ(query.exit_code, 0) << query.err;
  const nlohmann::json doc = nlohmann::json::parse(query.out);
  const nlohmann::json& r = doc["results"][0];
  EXPECT_EQ(r["status"], "ok");
  EXPECT_FALSE(r["intersecting"].get<bool>());
  ASSERT_EQ(r["contacts"].size(), 4u);
  for (const nlohmann::json& c : r["contacts"]) EXPECT_NEAR(c["depth"].get<double>(), -0.01, 1e-12);
  EXPECT_TRUE(doc["results"][1]["contacts"].empty());
  EXPECT_TRUE(doc["results"][2]["contacts"].empty());
  const RunResult check = run({"check", file});
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
}

TEST_F(SceneCli, BadContactDistancesAreErrorsNamingTheirPath) {
  const struct {
    std::string query, message;
  } cases[] = {
      {R"({"type": "contact", "a": "p", "b": "q", "contact_distance": -0.5})", "queries[0].contact_distance: negative"},
      {R"({"type": "contact", "a": "p", "b": "q", "contact_distance": "near"})",
       "queries[0].contact_distance: expected a number, got a string"},
      {R"({"type": "contact", "a": "p", "b": "q", "contact_distance": 1e61})",
       "queries[0].contact_distance: too large"},
      {R"({"type": "penetration", "a": "p", "b": "q", "contact_distance": 0.1})",
       "queries[0].contact_distance: unknown key"},
  };
  for (const auto& c : cases) {
    const std::string file = write("bad_contact_distance.json", scene(kTwoBalls, kTwoBallBodies, "[" + c.query + "]"));
    expect_bad({"query", file}, {file + ": " + c.message});
    expect_bad({"check", file}, {file + ": " + c.message});
  }
  // Not finite: JSON has no infinity, and a number beyond a double is malformed.
  const std::string inf = write(
      "inf.json",
      scene(kTwoBalls, kTwoBallBodies, R"([{"type": "contact", "a": "p", "b": "q", "contact_distance": 1e400}])"));
  expect_bad({"query", inf}, {inf + ":", "not a finite double"});
}

TEST_F(SceneCli, OneBadSceneFailsTheWholeCheck) {
  const std::string good = write("good.json", scene(kTwoBalls, kTwoBallBodies, kBallQuery));
  const std::string bad = write("bad.json", scene(R"({"ball": {"type": "sphere"}})", kTwoBallBodies, kBallQuery));
  expect_bad({"check", good, bad}, {bad + ": shapes.ball"});
  expect_bad({"check", good, (work_ / "absent.json").string()},
             {"absent.json: cannot open: No such file or directory"});
}

// ---- results ----------------------------------------------------------------

// Every field of the contract, of the right type, and the witness identity
// point_b - point_a = distance * normal.
void expect_well_formed(const nlohmann::json& r) {
  const std::vector<std::string> keys = {"a",       "b",      "type",     "intersecting", "distance", "point_a",
                                         "point_b", "normal", "contacts", "iterations",   "status",   "time_ns"};
  for (const std::string& key : keys) ASSERT_TRUE(r.contains(key)) << key << " in " << r.dump();
  EXPECT_TRUE(r["intersecting"].is_boolean());
  EXPECT_TRUE(r["contacts"].is_array());
  EXPECT_TRUE(r["iterations"]["gjk"].is_number_integer());
  EXPECT_TRUE(r["iterations"]["epa"].is_number_integer());
  EXPECT_EQ(r["status"], "ok");
  EXPECT_GE(r["time_ns"].get<double>(), 0.0);
  if (r["normal"].is_array()) {
    const Eigen::Vector3d n = vec(r["normal"]);
    EXPECT_NEAR(n.norm(), 1.0, 1e-15);
    const Eigen::Vector3d gap = vec(r["point_b"]) - vec(r["point_a"]);
    EXPECT_LE((gap - r["distance"].get<double>() * n).norm(), 1e-14) << r.dump();
  }
}

TEST_F(SceneCli, QueryJsonMatchesClosedForms) {
  // Balls of radius 1 at (0,0,0) and (3,4,0): distance 5 - 2 = 3, normal
  // (0.6, 0.8, 0), closest points at distance 1 from each centre.
  // Boxes: unit cubes (half 0.5), the second at (0.9, 0.2, 0) turned 90
  // degrees about z (the same cube): overlap 0.1 along x, 0.8 along y, so
  // depth 0.1 along +x.
  const std::string file = write(
      "pairs.json",
      scene(R"({"ball": {"type": "sphere", "radius": 1}, "cube": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}})",
            R"({"p": {"shape": "ball"}, "q": {"shape": "ball", "position": [3, 4, 0]},
                "c": {"shape": "cube"}, "d": {"shape": "cube", "position": [0.9, 0.2, 0], "orientation": [2, 0, 0, 2]}})",
            R"([{"a": "p", "b": "q", "type": "distance"}, {"a": "c", "b": "d", "type": "penetration"},
                {"a": "p", "b": "q", "type": "intersect"}, {"a": "c", "b": "d", "type": "distance"}])"));
  const nlohmann::json document = run_json({"query", file, "--json"});
  EXPECT_EQ(document["scene"], "pairs");
  ASSERT_EQ(document["results"].size(), 4u);
  for (const nlohmann::json& r : document["results"]) expect_well_formed(r);

  const nlohmann::json& balls = document["results"][0];
  EXPECT_EQ(balls["a"], "p");
  EXPECT_EQ(balls["b"], "q");
  EXPECT_EQ(balls["type"], "distance");
  EXPECT_EQ(balls["intersecting"], false);
  EXPECT_NEAR(balls["distance"].get<double>(), 3.0, 1e-14);
  EXPECT_LE((vec(balls["normal"]) - Eigen::Vector3d(0.6, 0.8, 0)).norm(), 1e-15);
  EXPECT_LE((vec(balls["point_a"]) - Eigen::Vector3d(0.6, 0.8, 0)).norm(), 1e-14);
  EXPECT_LE((vec(balls["point_b"]) - Eigen::Vector3d(2.4, 3.2, 0)).norm(), 1e-14);
  EXPECT_EQ(balls["iterations"]["epa"], 0);

  const nlohmann::json& boxes = document["results"][1];
  EXPECT_EQ(boxes["intersecting"], true);
  EXPECT_NEAR(boxes["distance"].get<double>(), -0.1, 1e-14);
  EXPECT_LE((vec(boxes["normal"]) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-14);
  EXPECT_GT(boxes["iterations"]["epa"].get<int>(), 0);

  // Values a query type does not define are null, never a made-up number.
  const nlohmann::json& intersect = document["results"][2];
  EXPECT_EQ(intersect["intersecting"], false);
  EXPECT_TRUE(intersect["distance"].is_null());
  EXPECT_TRUE(intersect["normal"].is_null());
  const nlohmann::json& overlapping = document["results"][3];
  EXPECT_EQ(overlapping["intersecting"], true);
  EXPECT_EQ(overlapping["distance"].get<double>(), 0.0);
  EXPECT_TRUE(overlapping["normal"].is_null());
  EXPECT_TRUE(overlapping["point_a"].is_null());
}

TEST_F(SceneCli, QueryTableForAPerson) {
  const std::string file = write("balls.json", scene(kTwoBalls, kTwoBallBodies, kBallQuery));
  const RunResult result = run({"query", file});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.err, "");
  EXPECT_TRUE(nlohmann::json::parse(result.out, nullptr, false).is_discarded()) << "a table, not JSON";
  EXPECT_NE(result.out.find("distance"), std::string::npos);
  EXPECT_NE(result.out.find(" 3 "), std::string::npos) << result.out;  // the distance
}

TEST_F(SceneCli, RepeatGivesTheSameAnswerAndAMedianTime) {
  const std::string file = write("balls.json", scene(kTwoBalls, kTwoBallBodies, kBallQuery));
  nlohmann::json once = run_json({"query", file, "--json"});
  nlohmann::json many = run_json({"query", file, "--json", "--repeat", "9"});
  EXPECT_GT(many["results"][0]["time_ns"].get<double>(), 0.0);
  once["results"][0].erase("time_ns");
  many["results"][0].erase("time_ns");
  EXPECT_EQ(many["timed_calls"], 9);
  for (const char* key : {"timing", "timed_calls"}) {
    once.erase(key);
    many.erase(key);
  }
  EXPECT_EQ(once, many);
  expect_bad({"query", file, "--repeat", "0"}, {"--repeat"});
  expect_bad({"query", file, "--repeat", "x"}, {"--repeat", "'x'"});
}

TEST_F(SceneCli, StatsShowWhatRan) {
  const std::string file =
      write("mixed.json", scene(R"({"cube": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
                "rock": {"type": "hull", "points": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]]},
                "unused": {"type": "hull", "points": [[0,0,0],[2,0,0],[0,2,0],[0,0,2]]}})",
                                R"({"c": {"shape": "cube"}, "d": {"shape": "cube", "position": [0.5, 0.5, 0.5]},
                "r": {"shape": "rock", "position": [0, 0, 3]}, "s": {"shape": "rock", "position": [0, 0, -3]}})",
                                R"([{"a": "c", "b": "d", "type": "intersect"}, {"a": "c", "b": "d", "type": "distance"},
                {"a": "c", "b": "d", "type": "penetration"}, {"a": "r", "b": "s", "type": "distance"},
                {"a": "c", "b": "r", "type": "penetration"}])"));
  const nlohmann::json document = run_json({"query", file, "--json", "--stats"});
  const nlohmann::json& results = document["results"];
  ASSERT_EQ(results.size(), 5u);
  for (const nlohmann::json& r : results) {
    ASSERT_TRUE(r.contains("stats")) << r.dump();
    EXPECT_EQ(r["stats"]["manifold_ran"], false);
    EXPECT_GT(r["stats"]["gjk_iterations"].get<int>(), 0);
    // GJK evaluates the pair's support once per iteration and once to start;
    // EPA at least once per iteration on top.
    EXPECT_GE(r["stats"]["support_calls"].get<int>(),
              r["stats"]["gjk_iterations"].get<int>() + 1 + r["stats"]["epa_iterations"].get<int>())
        << r.dump();
  }
  EXPECT_EQ(results[0]["stats"]["epa_ran"], false) << "intersect runs no EPA";
  EXPECT_EQ(results[1]["stats"]["epa_ran"], false) << "distance runs no EPA";
  EXPECT_EQ(results[2]["stats"]["epa_ran"], true) << "overlapping penetration runs EPA";
  EXPECT_GT(results[2]["stats"]["epa_iterations"].get<int>(), 0);
  EXPECT_EQ(results[4]["stats"]["epa_ran"], false) << "separated penetration needs no EPA";
  EXPECT_EQ(results[4]["intersecting"], false);
  // Two shapes used; the rock hull shared by r and s is built once, the
  // unused hull never.
  EXPECT_EQ(document["stats"]["shapes_defined"], 3);
  EXPECT_EQ(document["stats"]["shapes_built"], 2);
  EXPECT_EQ(document["stats"]["hulls_built"], 1);

  // Without --stats there are no stats fields.
  const nlohmann::json plain = run_json({"query", file, "--json"});
  EXPECT_FALSE(plain.contains("stats"));
  EXPECT_FALSE(plain["results"][0].contains("stats"));
}

TEST_F(SceneCli, SphereSceneBuildsNoHull) {
  // A hull is defined but no query uses it; its mesh file does not even exist.
  const std::string file = write(
      "balls.json", scene(R"({"ball": {"type": "sphere", "radius": 1}, "rock": {"type": "hull", "file": "rock.obj"}})",
                          kTwoBallBodies, kBallQuery));
  const nlohmann::json document = run_json({"query", file, "--json", "--stats"});
  EXPECT_EQ(document["stats"]["hulls_built"], 0);
  EXPECT_EQ(document["stats"]["mesh_files_read"], 0);
  EXPECT_EQ(document["stats"]["shapes_built"], 1);
  const RunResult text = run({"query", file, "--stats"});
  EXPECT_NE(text.out.find("1 of 2 shapes built (0 hulls"), std::string::npos) << text.out;
}

TEST_F(SceneCli, MeshFileRelativeToTheScene) {
  // The scene sits in a subdirectory; the test runs from elsewhere.
  fs::create_directories(work_ / "sub" / "meshes");
  write("sub/meshes/cube.obj", "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n");
  const std::string file =
      write("sub/scene.json",
            scene(R"({"cube": {"type": "hull", "file": "meshes/cube.obj"}, "ball": {"type": "sphere", "radius": 0.5}})",
                  R"({"c": {"shape": "cube"}, "b": {"shape": "ball", "position": [0, 0, 3]}})",
                  R"([{"a": "c", "b": "b", "type": "distance", "expect": {"distance": 1.5, "normal": [0, 0, 1]}}])"));
  const RunResult result = run({"check", file});
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  const nlohmann::json document = run_json({"query", file, "--json", "--stats"});
  EXPECT_EQ(document["stats"]["mesh_files_read"], 1);
  EXPECT_NEAR(document["results"][0]["distance"].get<double>(), 1.5, 1e-14);
}

// ---- check ------------------------------------------------------------------

TEST_F(SceneCli, CheckPassesAndFails) {
  const std::string queries =
      R"([{"a": "p", "b": "q", "type": "distance", "expect": {"distance": 3, "normal": [3, 4, 0]}},
          {"a": "p", "b": "q", "type": "penetration"},
          {"a": "p", "b": "q", "type": "intersect", "expect": {"intersecting": false}}])";
  const std::string good = write("good.json", scene(kTwoBalls, kTwoBallBodies, queries));
  const RunResult pass = run({"check", good});
  EXPECT_EQ(pass.exit_code, 0) << pass.out << pass.err;
  EXPECT_EQ(count_lines(pass.out, "PASS " + good + " ["), 3) << pass.out;
  EXPECT_NE(pass.out.find("3 queries in 1 scene: 3 passed, 0 failed"), std::string::npos) << pass.out;

  // A deliberately wrong distance (off by 1e-6, above the default tolerance
  // of 1e-9 of the pair's size), then a wrong verdict, then a normal off by
  // 1e-3 rad beyond an explicit angle tolerance.
  const std::string wrong_queries =
      R"([{"a": "p", "b": "q", "type": "distance", "expect": {"distance": 3.000001}},
          {"a": "p", "b": "q", "type": "intersect", "expect": {"intersecting": true}},
          {"a": "p", "b": "q", "type": "distance", "expect": {"normal": [0.6, 0.801, 0], "angle_tolerance": 1e-4}},
          {"a": "p", "b": "q", "type": "distance", "expect": {"distance": 3.000001, "tolerance": 1e-5}}])";
  const std::string bad = write("wrong.json", scene(kTwoBalls, kTwoBallBodies, wrong_queries));
  const RunResult fail = run({"check", good, bad});
  EXPECT_EQ(fail.exit_code, 1) << fail.out << fail.err;
  EXPECT_EQ(fail.err, "");
  EXPECT_EQ(count_lines(fail.out, "PASS " + good), 3) << fail.out;
  EXPECT_EQ(count_lines(fail.out, "FAIL " + bad + " [0] p-q distance: distance 3 (expected 3.000001"), 1) << fail.out;
  EXPECT_EQ(count_lines(fail.out, "FAIL " + bad + " [1] p-q intersect: intersecting false (expected true)"), 1)
      << fail.out;
  EXPECT_EQ(count_lines(fail.out, "FAIL " + bad + " [2] p-q distance: normal "), 1) << fail.out;
  EXPECT_EQ(count_lines(fail.out, "PASS " + bad + " [3]"), 1) << "an explicit tolerance widens: " << fail.out;
  EXPECT_NE(fail.out.find("7 queries in 2 scenes: 4 passed, 3 failed"), std::string::npos) << fail.out;
}

TEST_F(SceneCli, CheckFailsANormalTheQueryLeavesUndefined) {
  // Overlapping balls: a distance query defines no normal.
  const std::string file =
      write("o.json", scene(kTwoBalls, R"({"p": {"shape": "ball"}, "q": {"shape": "ball", "position": [1, 0, 0]}})",
                            R"([{"a": "p", "b": "q", "type": "distance", "expect": {"normal": [1, 0, 0]}}])"));
  const RunResult result = run({"check", file});
  EXPECT_EQ(result.exit_code, 1) << result.out << result.err;
  EXPECT_NE(result.out.find("normal undefined"), std::string::npos) << result.out;
}

TEST_F(SceneCli, RepositoryDemoSceneChecks) {
  const RunResult result = run({"check", HEDRA_SOURCE_DIR "/scenes/demo.json"});
  EXPECT_EQ(result.exit_code, 0) << result.out << result.err;
  EXPECT_EQ(count_lines(result.out, "FAIL"), 0) << result.out;
  EXPECT_GT(count_lines(result.out, "PASS"), 5);
}

TEST_F(SceneCli, OrientationIsNormalised) {
  // [1, 0, 3, 0] normalised is the turn about y by t = 2 atan(3), which maps
  // the capsule's axis z to (sin t, 0, cos t); the distance to a ball is
  // that of its centre to the segment minus both radii.
  const std::string file = write(
      "rot.json",
      scene(
          R"({"pill": {"type": "capsule", "radius": 0.25, "half_length": 1}, "ball": {"type": "sphere", "radius": 0.5}})",
          R"({"p": {"shape": "pill", "orientation": [1, 0, 3, 0]}, "b": {"shape": "ball", "position": [2, 0, 0]}})",
          R"([{"a": "p", "b": "b", "type": "distance"}])"));
  const double t = 2.0 * std::atan(3.0);
  const Eigen::Vector3d axis(std::sin(t), 0.0, std::cos(t));
  const Eigen::Vector3d centre(2, 0, 0);
  const double along = std::clamp(centre.dot(axis), -1.0, 1.0);
  const double expected = (centre - along * axis).norm() - 0.25 - 0.5;
  const nlohmann::json document = run_json({"query", file, "--json"});
  EXPECT_NEAR(document["results"][0]["distance"].get<double>(), expected, 1e-14);
}

}  // namespace

// ---- what a newcomer meets: clear refusals and honest tables ---------------

TEST_F(SceneCli, ABodyQueriedAgainstItselfIsRefused) {
  const std::string file =
      write("self.json", scene(kTwoBalls, kTwoBallBodies, R"([{"a": "p", "b": "p", "type": "penetration"}])"));
  expect_bad({"query", file}, {file + ": queries[0].b: the same body as 'a' ('p')", "not queried against itself"});
}

TEST_F(SceneCli, AnUnknownBodyOrShapeGetsADidYouMean) {
  const std::string body =
      write("body.json",
            scene(kTwoBalls, R"({"crate": {"shape": "ball"}, "floor": {"shape": "ball", "position": [5, 0, 0]}})",
                  R"([{"a": "crat", "b": "floor", "type": "distance"}])"));
  expect_bad({"query", body}, {body + ": queries[0].a: unknown body 'crat' (did you mean 'crate'?)"});
  const std::string shape =
      write("shape.json",
            scene(kTwoBalls, R"({"p": {"shape": "Ball"}, "q": {"shape": "ball", "position": [5, 0, 0]}})", kBallQuery));
  expect_bad({"query", shape}, {shape + ": bodies.p.shape: unknown shape 'Ball' (did you mean 'ball'?)"});
  // Nothing close: the known names instead of a guess.
  const std::string far =
      write("far.json", scene(kTwoBalls, kTwoBallBodies, R"([{"a": "zebra", "b": "q", "type": "distance"}])"));
  const RunResult r = expect_bad({"query", far}, {far + ": queries[0].a: unknown body 'zebra' (known: p, q)"});
  EXPECT_EQ(r.err.find("did you mean"), std::string::npos) << r.err;
}

// An unknown `expect` key lists the keys that query type answers, not those
// of the continuous queries (hit, fraction).
TEST_F(SceneCli, UnknownExpectKeysListWhatTheQueryTypeAnswers) {
  const auto message = [&](const std::string& type) {
    const std::string file =
        write(type + ".json", scene(kTwoBalls, kTwoBallBodies,
                                    R"([{"a": "p", "b": "q", "type": ")" + type + R"(", "expect": {"depth": 1}}])"));
    return expect_bad({"query", file}, {file + ": queries[0].expect.depth: unknown key"}).err;
  };
  const std::string contact = message("contact");
  EXPECT_NE(contact.find("a 'contact' query may expect: intersecting, distance, normal, tolerance, angle_tolerance, "
                         "contact_count"),
            std::string::npos)
      << contact;
  EXPECT_EQ(contact.find("fraction"), std::string::npos) << contact;
  const std::string intersect = message("intersect");
  EXPECT_NE(intersect.find("an 'intersect' query may expect: intersecting)"), std::string::npos) << intersect;
  EXPECT_EQ(message("distance").find("contact_count"), std::string::npos);
  // "an 'intersect' query", not "a 'intersect' query".
  const std::string file = write(
      "i.json",
      scene(kTwoBalls, kTwoBallBodies, R"([{"a": "p", "b": "q", "type": "intersect", "expect": {"hit": true}}])"));
  const RunResult r = expect_bad({"query", file}, {"an 'intersect' query has no 'hit'"});
  EXPECT_EQ(r.err.find("a 'intersect'"), std::string::npos) << r.err;
}

// Every query is timed warm (one untimed call first) and the output says
// so; time_ns is a whole number of nanoseconds.
TEST_F(SceneCli, TimesAreWarmMediansAndSaySo) {
  const std::string file = write("balls.json", scene(kTwoBalls, kTwoBallBodies, kBallQuery));
  const RunResult table = run({"query", file, "--repeat", "5"});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("times: warm (1 untimed call first), median of 5 timed calls"), std::string::npos)
      << table.out;
  const nlohmann::json document = run_json({"query", file, "--json"});
  EXPECT_EQ(document["timing"], "times: warm (1 untimed call first), median of 1 timed call");
  EXPECT_TRUE(document["results"][0]["time_ns"].is_number_integer()) << document.dump();
}

// The table's fourth column says what it means: overlap/apart for discrete
// queries, hit/miss for continuous ones; a ray is ray-<body>; a cast's
// distance is never printed below its target.
TEST_F(SceneCli, QueryTableColumnsSayWhatTheyMean) {
  const std::string file =
      write("mixed.json",
            scene(R"({"ball": {"type": "sphere", "radius": 1}, "crate": {"type": "box", "half_extents": [1, 1, 1]}})",
                  R"({"p": {"shape": "ball"}, "q": {"shape": "ball", "position": [1.5, 0, 0]},
                "box": {"shape": "crate", "position": [10, 0, 0]},
                "mover": {"shape": "crate", "position": [0, 0, 5], "end_position": [0, 0, -1]},
                "still": {"shape": "crate", "position": [0.3, 0.2, 0]}})",
                  R"([{"a": "p", "b": "q", "type": "intersect"}, {"a": "p", "b": "box", "type": "distance"},
                {"type": "raycast", "body": "box", "origin": [0, 0, 0], "direction": [20, 0, 0]},
                {"a": "mover", "b": "still", "type": "cast"}])"));
  const RunResult r = run({"query", file});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream lines(r.out);
  std::vector<std::string> rows;
  for (std::string line; std::getline(lines, line);) rows.push_back(line);
  ASSERT_GE(rows.size(), 6u) << r.out;
  EXPECT_NE(rows[1].find("answer"), std::string::npos) << rows[1];
  EXPECT_EQ(rows[1].find(" hit "), std::string::npos) << rows[1];
  EXPECT_NE(rows[2].find(" overlap "), std::string::npos) << rows[2];
  EXPECT_NE(rows[3].find(" apart "), std::string::npos) << rows[3];
  EXPECT_NE(rows[4].find("  ray          box "), std::string::npos) << rows[4];
  EXPECT_NE(rows[4].find(" hit "), std::string::npos) << rows[4];
  EXPECT_NE(rows[5].find(" hit "), std::string::npos) << rows[5];
  EXPECT_EQ(rows[5].find("d=-"), std::string::npos) << rows[5];
  // Columns line up: every row's time column ends where the header's does.
  for (std::size_t i = 2; i < 6; ++i) EXPECT_EQ(rows[i].size(), rows[1].size()) << rows[i] << "\n" << rows[1];
  const nlohmann::json document = run_json({"query", file, "--json"});
  EXPECT_GE(document["results"][3]["distance"].get<double>(), 0.0) << document["results"][3].dump();
}
