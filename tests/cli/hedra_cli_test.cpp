// End-to-end tests of the `hedra` executable: each case writes its input
// files into a fresh temporary directory, runs the binary (path baked in by
// CMake as HEDRA_EXE) with posix_spawn, stdout and stderr captured to files,
// and checks the contract of scene-format.md: exit code 0 or 2, nothing on
// stdout for bad input, stderr naming the file and line, JSON that parses
// and is right, and --out leaving nothing behind when it fails.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <hedra/hull/mesh_io.hpp>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_fixture.hpp"

namespace {

using namespace hedra::cli_test;
namespace fs = std::filesystem;

const char* kCubeXyz =
    "# unit cube corners\n"
    "0 0 0\n1 0 0\n0 1 0\n1 1 0\n"
    "0 0 1\n1 0 1\n0 1 1\n1 1 1\n";

const char* kCubeObj =
    "o cube\n"
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
    "v 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
    "f 1 2 3\n";

const char* kCubeOff =
    "OFF\n8 0 0\n"
    "0 0 0\n1 0 0\n0 1 0\n1 1 0\n"
    "0 0 1\n1 0 1\n0 1 1\n1 1 1\n";

// Checks the JSON of the unit cube's hull: counts, volume, area, vertices
// being the 8 corners, faces being the 6 unit squares, counter-clockwise
// seen from outside.
void expect_unit_cube(const nlohmann::json& hull) {
  ASSERT_TRUE(hull.is_object());
  const std::vector<std::string> keys = {"vertex_count",         "edge_count", "face_count", "volume", "area",
                                         "max_outside_distance", "time_ns",    "vertices",   "faces"};
  for (const std::string& key : keys) ASSERT_TRUE(hull.contains(key)) << key;
  EXPECT_EQ(hull.size(), keys.size()) << "no undocumented fields: " << hull.dump();
  EXPECT_EQ(hull["vertex_count"], 8);
  EXPECT_EQ(hull["edge_count"], 12);
  EXPECT_EQ(hull["face_count"], 6);
  EXPECT_NEAR(hull["volume"].get<double>(), 1.0, 1e-12);
  EXPECT_NEAR(hull["area"].get<double>(), 6.0, 1e-12);
  EXPECT_LE(hull["max_outside_distance"].get<double>(), 1e-12);
  EXPECT_GE(hull["max_outside_distance"].get<double>(), 0.0);
  EXPECT_GE(hull["time_ns"].get<double>(), 0.0);

  std::vector<Eigen::Vector3d> vertices;
  std::set<std::vector<double>> corners;
  for (const nlohmann::json& v : hull["vertices"]) {
    ASSERT_TRUE(v.is_array() && v.size() == 3) << v.dump();
    vertices.emplace_back(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    corners.insert({v[0].get<double>(), v[1].get<double>(), v[2].get<double>()});
  }
  ASSERT_EQ(vertices.size(), 8u);
  EXPECT_EQ(corners.size(), 8u);
  for (const std::vector<double>& c : corners) {
    for (double x : c) EXPECT_TRUE(x == 0.0 || x == 1.0) << "not a cube corner";
  }
  ASSERT_EQ(hull["faces"].size(), 6u);
  std::set<std::pair<int, double>> planes;  // (axis, value) of each face
  for (const nlohmann::json& face : hull["faces"]) {
    ASSERT_EQ(face.size(), 4u) << "coplanar triangles must be merged: " << face.dump();
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // Newell
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < face.size(); ++i) {
      const std::size_t a = face[i].get<std::size_t>();
      const std::size_t b = face[(i + 1) % face.size()].get<std::size_t>();
      ASSERT_LT(a, vertices.size());
      ASSERT_LT(b, vertices.size());
      normal += vertices[a].cross(vertices[b]);
      centre += vertices[a] / 4.0;
    }
    // Counter-clockwise from outside: the normal points away from the cube's centre.
    EXPECT_GT(normal.dot(centre - Eigen::Vector3d(0.5, 0.5, 0.5)), 0.0) << face.dump();
    int axis = 0;
    normal.cwiseAbs().maxCoeff(&axis);
    EXPECT_NEAR(normal.norm(), 2.0, 1e-12);  // Newell gives twice the area
    planes.insert({axis, centre[axis]});
  }
  EXPECT_EQ(planes.size(), 6u) << "every side of the cube exactly once";
}

// ---- good input -------------------------------------------------------------

TEST_F(HedraCli, CubeCornersJson) {
  const std::string input = write("cube.xyz", kCubeXyz);
  expect_unit_cube(run_json({"hull", input, "--json"}));
}

TEST_F(HedraCli, CubeCornersFromObjAndOff) {
  expect_unit_cube(run_json({"hull", write("cube.obj", kCubeObj), "--json"}));
  expect_unit_cube(run_json({"hull", write("cube.off", kCubeOff), "--json"}));
}

TEST_F(HedraCli, CubeCornersSummaryForAPerson) {
  const RunResult result = run({"hull", write("cube.xyz", kCubeXyz)});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.err, "");
  EXPECT_NE(result.out.find("vertices              8\n"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("faces                 6\n"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("volume                1\n"), std::string::npos) << result.out;
  EXPECT_TRUE(nlohmann::json::parse(result.out, nullptr, false).is_discarded()) << "a summary, not JSON";
}

TEST_F(HedraCli, RepeatReportsMedianTime) {
  const nlohmann::json hull = run_json({"hull", write("cube.xyz", kCubeXyz), "--json", "--repeat", "7"});
  expect_unit_cube(hull);
  EXPECT_GT(hull["time_ns"].get<double>(), 0.0);
  EXPECT_TRUE(hull["time_ns"].is_number_integer()) << hull.dump();  // whole nanoseconds
}

// The build time in a unit a person reads (ns, us or ms, as `query` prints
// times), never millions of microseconds.
TEST_F(HedraCli, BuildTimeInAReadableUnit) {
  const RunResult result = run({"hull", write("cube.xyz", kCubeXyz)});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::size_t at = result.out.find("build time");
  ASSERT_NE(at, std::string::npos) << result.out;
  const std::string line = result.out.substr(at, result.out.find('\n', at) - at);
  const std::size_t digits = line.find_first_of("0123456789");
  ASSERT_NE(digits, std::string::npos) << line;
  const double value = std::stod(line.substr(digits));
  const std::string unit = line.substr(line.find(' ', digits) + 1, 2);
  EXPECT_TRUE(unit == "ns" || unit == "us" || unit == "ms") << line;
  EXPECT_LT(value, 10000.0) << line;
}

TEST_F(HedraCli, FlatInputGivesAPolygon) {
  const nlohmann::json hull = run_json({"hull", write("square.xyz", "0 0 0\n2 0 0\n2 3 0\n0 3 0\n1 1 0\n"), "--json"});
  EXPECT_EQ(hull["vertex_count"], 4);
  EXPECT_EQ(hull["volume"].get<double>(), 0.0);
  for (const nlohmann::json& face : hull["faces"]) EXPECT_EQ(face.size(), 4u);
}

TEST_F(HedraCli, DemoPointCloud) {
  const nlohmann::json hull = run_json({"hull", HEDRA_SOURCE_DIR "/tools/cli/data/demo_points.xyz", "--json"});
  const long long v = hull["vertex_count"];
  const long long e = hull["edge_count"];
  const long long f = hull["face_count"];
  EXPECT_EQ(v - e + f, 2);
  EXPECT_GT(v, 4);
  EXPECT_LT(v, 200);  // 50 of the points are strictly inside
  EXPECT_EQ(hull["vertices"].size(), static_cast<std::size_t>(v));
  EXPECT_EQ(hull["faces"].size(), static_cast<std::size_t>(f));
  EXPECT_GT(hull["volume"].get<double>(), 0.5);
  EXPECT_LE(hull["max_outside_distance"].get<double>(), 1e-12);
}

TEST_F(HedraCli, OutWritesTheHullAsObj) {
  const std::string input = write("cube.xyz", kCubeXyz);
  const std::string out = (work_ / "hull.obj").string();
  const RunResult result = run({"hull", input, "--out", out});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(listing(work_), (std::set<std::string>{"cube.xyz", "hull.obj"})) << "no temporary file left";
  const hedra::hull::ReadPointsResult back = hedra::hull::read_points(out);
  ASSERT_TRUE(back.ok()) << back.error->message();
  EXPECT_EQ(back.points.size(), 8u);
  const std::string text = slurp(out);
  EXPECT_EQ(count_lines(text, "f "), 6);

  ASSERT_EQ(run({"hull", input, "--out", out, "--triangulate"}).exit_code, 0);
  const std::string triangles = slurp(out);
  EXPECT_EQ(count_lines(triangles, "f "), 12) << "the existing file is replaced";
  EXPECT_EQ(listing(work_), (std::set<std::string>{"cube.xyz", "hull.obj"}));
}

// ---- bad input: exit 2, nothing on stdout, the file and line on stderr -----

TEST_F(HedraCli, MalformedLine) {
  const std::string input = write("bad.xyz", "0 0 0\n1 0 0\n0 1\n0 0 1\n");
  expect_bad({"hull", input, "--json"}, {input + ":3: ", "expected 3 numbers"});
  const std::string obj = write("bad.obj", "v 0 0 0\n# comment\nv 1 zero 0\n");
  expect_bad({"hull", obj}, {obj + ":3: ", "'zero' is not a number"});
}

TEST_F(HedraCli, NaN) {
  const std::string input = write("nan.xyz", "0 0 0\nnan 1 0\n0 0 1\n1 1 1\n");
  expect_bad({"hull", input, "--json"}, {input + ":2: ", "non-finite"});
  const std::string huge = write("huge.off", "OFF\n4 0 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1e999\n");
  expect_bad({"hull", huge}, {huge + ":6: "});
}

TEST_F(HedraCli, EmptyFile) {
  const std::string input = write("empty.xyz", "");
  expect_bad({"hull", input, "--json"}, {input + ": ", "no points"});
}

TEST_F(HedraCli, MissingFile) {
  const std::string input = (work_ / "missing.xyz").string();
  expect_bad({"hull", input, "--json"}, {input + ": ", "cannot open"});
}

TEST_F(HedraCli, UnknownExtension) {
  const std::string input = write("cloud.ply", "0 0 0\n");
  expect_bad({"hull", input}, {input + ": ", "unknown file extension"});
}

TEST_F(HedraCli, RepeatMustBePositive) {
  const std::string input = write("cube.xyz", kCubeXyz);
  expect_bad({"hull", input, "--json", "--repeat", "0"}, {"--repeat"});
  expect_bad({"hull", input, "--json", "--repeat", "-3"}, {"--repeat"});
  expect_bad({"hull", input, "--json", "--repeat=-1"}, {"--repeat"});
  expect_bad({"hull", input, "--json", "--repeat", "many"}, {"--repeat", "'many'"});
  expect_bad({"hull", input, "--json", "--repeat"}, {"--repeat"});
}

TEST_F(HedraCli, UnwritableOutCreatesNothing) {
  const std::string input = write("cube.xyz", kCubeXyz);
  const std::set<std::string> before = listing(work_);
  // A directory that does not exist.
  const std::string in_missing_dir = (work_ / "no_such_dir" / "hull.obj").string();
  expect_bad({"hull", input, "--out", in_missing_dir}, {in_missing_dir});
  // A path through a regular file.
  const std::string through_file = (work_ / "cube.xyz" / "hull.obj").string();
  expect_bad({"hull", input, "--out", through_file}, {through_file});
  // An existing directory.
  fs::create_directories(work_ / "somedir");
  const std::string directory = (work_ / "somedir").string();
  expect_bad({"hull", input, "--out", directory}, {directory, "is a directory"});
  EXPECT_TRUE(fs::is_empty(work_ / "somedir"));
  fs::remove(work_ / "somedir");
  EXPECT_EQ(listing(work_), before) << "nothing created beside the input";
}

TEST_F(HedraCli, BadInputLeavesOutUntouched) {
  const std::string input = write("bad.xyz", "0 0 0\n1 1\n");
  const std::string out = write("hull.obj", "previous contents\n");
  expect_bad({"hull", input, "--out", out}, {input + ":2: "});
  EXPECT_EQ(slurp(out), "previous contents\n");
  EXPECT_EQ(listing(work_), (std::set<std::string>{"bad.xyz", "hull.obj"}));
}

TEST_F(HedraCli, UsageErrors) {
  expect_bad({}, {"subcommand"});
  expect_bad({"frobnicate"}, {"unknown subcommand 'frobnicate'"});
  expect_bad({"hull"}, {"input"});
  expect_bad({"hull", write("cube.xyz", kCubeXyz), "--no-such-option"}, {"--no-such-option"});
  expect_bad({"hull", write("cube.xyz", kCubeXyz), "--triangulate"}, {"--out"});
}

TEST_F(HedraCli, HelpGoesToStdout) {
  const RunResult result = run({"hull", "--help"});
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_NE(result.out.find("--repeat"), std::string::npos) << result.out;
}

}  // namespace
