// Tests of the point readers (.xyz, .obj, .off) and the OBJ writer.
//
// Each malformed case checks the exact location the message names (file and
// 1-based line) and the gist of the reason; well-formed cases check every
// coordinate exactly. The writer is checked by a bit-exact round trip through
// the reader, and its faces against the mesh's own polygons and planes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <hedra/hull/half_edge_mesh.hpp>
#include <hedra/hull/mesh_io.hpp>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace hedra::hull {
namespace {

using Points = std::vector<Eigen::Vector3d>;

ReadPointsResult read_text(const std::string& text, PointFormat format, const std::string& name = "test") {
  std::istringstream in(text);
  return read_points(in, format, name);
}

// Expects failure at `line` with a message that starts with "name:line:" and
// contains `gist`.
void expect_error(const ReadPointsResult& result, const std::string& name, std::size_t line, const std::string& gist) {
  ASSERT_FALSE(result.ok()) << "expected an error mentioning " << gist;
  EXPECT_TRUE(result.points.empty());
  EXPECT_EQ(result.error->file, name);
  EXPECT_EQ(result.error->line, line) << result.error->message();
  const std::string message = result.error->message();
  const std::string location = line > 0 ? name + ":" + std::to_string(line) + ": " : name + ": ";
  EXPECT_EQ(message.rfind(location, 0), 0u) << message;
  EXPECT_NE(message.find(gist), std::string::npos) << message;
}

void expect_points(const ReadPointsResult& result, const Points& expected) {
  ASSERT_TRUE(result.ok()) << result.error->message();
  ASSERT_EQ(result.points.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      // Exact comparison: the reader must convert decimals correctly rounded.
      EXPECT_EQ(result.points[i][k], expected[i][k]) << "point " << i << " coordinate " << k;
    }
  }
}

// ---- .xyz -----------------------------------------------------------------

TEST(ReadXyz, ReadsPointsSkippingCommentsAndBlankLines) {
  const std::string text =
      "# a header comment\n"
      "\n"
      "1 2 3\n"
      "  -0.5\t+4e2   1.25e-3   # trailing comment\n"
      "\t\n"
      ".5 5. -0\r\n";
  expect_points(read_text(text, PointFormat::xyz), {{1, 2, 3}, {-0.5, 400, 1.25e-3}, {0.5, 5, -0.0}});
  EXPECT_TRUE(std::signbit(read_text(text, PointFormat::xyz).points[2].z()));
}

TEST(ReadXyz, LastLineWithoutNewline) {
  expect_points(read_text("1 2 3\n4 5 6", PointFormat::xyz), {{1, 2, 3}, {4, 5, 6}});
}

TEST(ReadXyz, ConvertsDecimalsCorrectlyRounded) {
  const ReadPointsResult result = read_text("0.1 0.2 0.30000000000000004\n", PointFormat::xyz);
  expect_points(result, {{0.1, 0.2, 0.1 + 0.2}});
}

TEST(ReadXyz, TooFewNumbersNamesTheLine) {
  expect_error(read_text("1 2 3\n# comment\n4 5\n", PointFormat::xyz, "rock.xyz"), "rock.xyz", 3,
               "expected 3 numbers (x y z), found 2");
}

TEST(ReadXyz, TooManyNumbersNamesTheLine) {
  expect_error(read_text("1 2 3 4\n", PointFormat::xyz, "rock.xyz"), "rock.xyz", 1, "found 4");
}

TEST(ReadXyz, WordIsNotANumber) {
  expect_error(read_text("1 2 3\n1 two 3\n", PointFormat::xyz, "a.xyz"), "a.xyz", 2, "'two' is not a number");
}

TEST(ReadXyz, TrailingGarbageIsNotANumber) {
  expect_error(read_text("1 2 3abc\n", PointFormat::xyz, "a.xyz"), "a.xyz", 1, "'3abc' is not a number");
  expect_error(read_text("1 2 ++3\n", PointFormat::xyz, "a.xyz"), "a.xyz", 1, "'++3' is not a number");
  expect_error(read_text("1 2 +-3\n", PointFormat::xyz, "a.xyz"), "a.xyz", 1, "'+-3' is not a number");
  expect_error(read_text("1 2 0x10\n", PointFormat::xyz, "a.xyz"), "a.xyz", 1, "'0x10' is not a number");
  expect_error(read_text("1 2 1,5\n", PointFormat::xyz, "a.xyz"), "a.xyz", 1, "'1,5' is not a number");
}

TEST(ReadXyz, RejectsNonFiniteNumbers) {
  for (const char* bad : {"nan", "NaN", "-nan", "inf", "-inf", "infinity", "+inf"}) {
    SCOPED_TRACE(bad);
    expect_error(read_text(std::string("0 0 0\n1 ") + bad + " 2\n", PointFormat::xyz, "p.xyz"), "p.xyz", 2,
                 "non-finite number");
  }
}

TEST(ReadXyz, RejectsNumbersTooLargeForADouble) {
  for (const char* bad : {"1e999", "-1e999", "1e400", "123456789e301", "0.0001e313", "2e308"}) {
    SCOPED_TRACE(bad);
    expect_error(read_text(std::string("1 ") + bad + " 2\n", PointFormat::xyz, "p.xyz"), "p.xyz", 1,
                 "too large for a double");
  }
}

TEST(ReadXyz, NumbersTooSmallForADoubleRoundToZero) {
  const ReadPointsResult result = read_text("1e-400 -1000e-327 0.000001e-320\n", PointFormat::xyz);
  expect_points(result, {{0, 0, 0}});
  EXPECT_TRUE(std::signbit(result.points[0].y()));
  // The smallest subnormal is still representable.
  expect_points(read_text("4.9406564584124654e-324 0 1.7976931348623157e308\n", PointFormat::xyz),
                {{std::numeric_limits<double>::denorm_min(), 0, std::numeric_limits<double>::max()}});
}

TEST(ReadXyz, EmptyInputIsAnError) {
  expect_error(read_text("", PointFormat::xyz, "e.xyz"), "e.xyz", 0, "no points");
  expect_error(read_text("# only a comment\n\n   \n", PointFormat::xyz, "e.xyz"), "e.xyz", 0, "no points");
}

// ---- .obj -----------------------------------------------------------------

TEST(ReadObj, ReadsVertexLinesOnly) {
  const std::string text =
      "# exported\n"
      "mtllib rock.mtl\n"
      "o rock\n"
      "v 0 0 0\n"
      "vt 0.5 0.5\n"
      "vn 0 0 1\n"
      "v 1 0 0 1.0\n"          // with w
      "v 0 1 0 0.1 0.2 0.3\n"  // with a colour
      "g side\n"
      "usemtl stone\n"
      "f 1/1/1 2/1/1 3/1/1\n"
      "s off\n"
      "v\t0 0 1   # apex\r\n";
  expect_points(read_text(text, PointFormat::obj), {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
}

TEST(ReadObj, MessageNamesFileAndLine) {
  std::string text;
  for (int i = 0; i < 16; ++i) text += "v " + std::to_string(i) + " 0 0\n";
  text += "v 1 2\n";
  const ReadPointsResult result = read_text(text, PointFormat::obj, "rock.obj");
  expect_error(result, "rock.obj", 17, "expected 3 numbers after 'v'");
  EXPECT_EQ(result.error->message().rfind("rock.obj:17: expected 3 numbers after 'v'", 0), 0u);
}

TEST(ReadObj, WrongNumberOfCoordinates) {
  expect_error(read_text("v\n", PointFormat::obj, "m.obj"), "m.obj", 1, "found 0");
  expect_error(read_text("v 1 2 3 4 5\n", PointFormat::obj, "m.obj"), "m.obj", 1, "found 5");
  expect_error(read_text("v 1 2 3 4 5 6 7\n", PointFormat::obj, "m.obj"), "m.obj", 1, "found 7");
}

TEST(ReadObj, BadNumbers) {
  expect_error(read_text("v 0 0 0\nv 1 x 0\n", PointFormat::obj, "m.obj"), "m.obj", 2, "'x' is not a number");
  expect_error(read_text("v 1 1 nan\n", PointFormat::obj, "m.obj"), "m.obj", 1, "non-finite");
  expect_error(read_text("v 1 1 1e999\n", PointFormat::obj, "m.obj"), "m.obj", 1, "too large");
  // The optional w and colours must be numbers too.
  expect_error(read_text("v 1 1 1 w\n", PointFormat::obj, "m.obj"), "m.obj", 1, "'w' is not a number");
  expect_error(read_text("v 1 1 1 0 0 inf\n", PointFormat::obj, "m.obj"), "m.obj", 1, "non-finite");
}

TEST(ReadObj, FileWithoutVerticesIsAnError) {
  expect_error(read_text("o empty\nf 1 2 3\n", PointFormat::obj, "m.obj"), "m.obj", 0, "no points");
}

// ---- .off -----------------------------------------------------------------

TEST(ReadOff, ReadsVerticesAndIgnoresFaces) {
  const std::string text =
      "OFF\n"
      "# a tetrahedron\n"
      "4 4 6\n"
      "0 0 0\n"
      "\n"
      "1 0 0   # x\n"
      "0 1 0\n"
      "0 0 1\n"
      "3 0 2 1\n"
      "3 0 1 3 255 0 0\n"
      "these face lines are not read at all\n";
  expect_points(read_text(text, PointFormat::off), {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
}

TEST(ReadOff, CountsOnTheHeaderLine) {
  expect_points(read_text("OFF 2 0 0\n1 2 3\n4 5 6\n", PointFormat::off), {{1, 2, 3}, {4, 5, 6}});
}

TEST(ReadOff, MissingHeader) {
  expect_error(read_text("\n# c\n4 4 6\n", PointFormat::off, "t.off"), "t.off", 3, "expected the header 'OFF'");
}

TEST(ReadOff, UnsupportedVariant) {
  expect_error(read_text("COFF\n1 0 0\n0 0 0 255 0 0 255\n", PointFormat::off, "t.off"), "t.off", 1,
               "unsupported OFF variant 'COFF'");
}

TEST(ReadOff, BadCounts) {
  expect_error(read_text("OFF\n4 4\n", PointFormat::off, "t.off"), "t.off", 2, "3 non-negative integers");
  expect_error(read_text("OFF\n-4 4 6\n", PointFormat::off, "t.off"), "t.off", 2, "3 non-negative integers");
  expect_error(read_text("OFF\n4.5 4 6\n", PointFormat::off, "t.off"), "t.off", 2, "3 non-negative integers");
  expect_error(read_text("OFF\n99999999999999999999999 4 6\n", PointFormat::off, "t.off"), "t.off", 2,
               "3 non-negative integers");
  expect_error(read_text("OFF\n", PointFormat::off, "t.off"), "t.off", 1, "expected the counts line");
  expect_error(read_text("OFF\n0 0 0\n", PointFormat::off, "t.off"), "t.off", 2, "the vertex count is 0");
}

TEST(ReadOff, TruncatedVertexList) {
  expect_error(read_text("OFF\n3 1 0\n0 0 0\n1 0 0\n", PointFormat::off, "t.off"), "t.off", 4, "read 2 of 3 vertices");
  // An absurd count must not allocate it up front.
  expect_error(read_text("OFF\n1000000000000 0 0\n0 0 0\n", PointFormat::off, "t.off"), "t.off", 3,
               "read 1 of 1000000000000 vertices");
}

TEST(ReadOff, MalformedVertexLine) {
  expect_error(read_text("OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n", PointFormat::off, "t.off"), "t.off", 4,
               "vertex 2 of 3, found 2");
  expect_error(read_text("OFF\n1 0 0\nnan 0 0\n", PointFormat::off, "t.off"), "t.off", 3, "non-finite");
}

TEST(ReadOff, EmptyFile) { expect_error(read_text("", PointFormat::off, "t.off"), "t.off", 0, "no points"); }

// ---- files ----------------------------------------------------------------

class ReadFile : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("hedra_mesh_io_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  std::filesystem::path dir_;
};

TEST_F(ReadFile, ChoosesTheFormatByExtension) {
  expect_points(read_points(write("p.xyz", "1 2 3\n")), {{1, 2, 3}});
  expect_points(read_points(write("p.OBJ", "v 1 2 3\n")), {{1, 2, 3}});
  expect_points(read_points(write("p.Off", "OFF\n1 0 0\n1 2 3\n")), {{1, 2, 3}});
  EXPECT_EQ(format_from_path("a/b.c/rock.XyZ"), PointFormat::xyz);
  EXPECT_EQ(format_from_path("rock.obj.bak"), std::nullopt);
}

TEST_F(ReadFile, ErrorsNameThePathAsGiven) {
  const std::string path = write("bad.obj", "v 0 0 0\nv 1 1\n");
  expect_error(read_points(path), path, 2, "expected 3 numbers after 'v'");
}

TEST_F(ReadFile, UnknownExtension) {
  const std::string path = write("cloud.ply", "1 2 3\n");
  expect_error(read_points(path), path, 0, "unknown file extension '.ply' (expected .xyz, .obj or .off)");
  const std::string bare = write("cloud", "1 2 3\n");
  expect_error(read_points(bare), bare, 0, "no file extension");
}

TEST_F(ReadFile, MissingFile) {
  const std::string path = (dir_ / "missing.xyz").string();
  expect_error(read_points(path), path, 0, "cannot open: No such file or directory");
}

TEST_F(ReadFile, DirectoryIsNotAFile) {
  std::filesystem::create_directories(dir_ / "d.xyz");
  const std::string path = (dir_ / "d.xyz").string();
  expect_error(read_points(path), path, 0, "is a directory");
}

TEST_F(ReadFile, EmptyFile) {
  const std::string path = write("empty.xyz", "");
  expect_error(read_points(path), path, 0, "no points found");
}

// ---- writer ---------------------------------------------------------------

// A box [lo, hi] as a half-edge mesh, built without the hull builder.
HalfEdgeMesh make_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i) {
    corners.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z());
  }
  // Counter-clockwise seen from outside.
  const std::vector<std::vector<Index>> faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                                 {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  HalfEdgeMesh mesh;
  std::string error;
  EXPECT_TRUE(HalfEdgeMesh::from_polygons(corners, faces, mesh, &error)) << error;
  return mesh;
}

struct ObjFaces {
  std::vector<std::vector<Index>> faces;  // 0-based
};

ObjFaces parse_faces(const std::string& text) {
  ObjFaces result;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("f ", 0) != 0) continue;
    std::istringstream fields(line.substr(2));
    std::vector<Index> face;
    long long index = 0;
    while (fields >> index) {
      EXPECT_GE(index, 1) << line;  // OBJ indices are 1-based
      face.push_back(static_cast<Index>(index - 1));
    }
    EXPECT_TRUE(fields.eof()) << "unparsable face line: " << line;
    result.faces.push_back(face);
  }
  return result;
}

TEST(WriteObj, RoundTripIsBitExact) {
  // Coordinates that %.6g or shortest-float printing would spoil.
  const HalfEdgeMesh mesh = make_box({0.1, -1.0 / 3.0, 1e-300}, {2.5e300, 2.0 / 3.0, 4.9406564584124654e-324 * 7});
  std::ostringstream out;
  write_obj(mesh, out, false);
  ASSERT_TRUE(out.good());
  const ReadPointsResult back = read_text(out.str(), PointFormat::obj, "round_trip.obj");
  ASSERT_TRUE(back.ok()) << back.error->message();
  ASSERT_EQ(back.points.size(), mesh.vertex_count());
  for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(back.points[i][k], mesh.position(static_cast<Index>(i))[k]);
  }
  EXPECT_NE(out.str().find("v 0.10000000000000001 "), std::string::npos) << out.str();
}

TEST(WriteObj, PolygonFacesMatchTheMesh) {
  const HalfEdgeMesh mesh = make_box({0, 0, 0}, {1, 1, 1});
  std::ostringstream out;
  write_obj(mesh, out, false);
  const ObjFaces written = parse_faces(out.str());
  EXPECT_EQ(written.faces, mesh.polygons());
  EXPECT_EQ(out.str().rfind("# hedra convex hull: 8 vertices, 6 faces\n", 0), 0u) << out.str();
}

TEST(WriteObj, TriangulatedFacesCoverEachFaceAndPointOut) {
  const HalfEdgeMesh mesh = make_box({-1, -2, -3}, {1, 2, 3});
  std::ostringstream out;
  write_obj(mesh, out, true);
  const ObjFaces written = parse_faces(out.str());
  ASSERT_EQ(written.faces.size(), 12u);
  double area = 0.0;
  std::set<std::set<Index>> covered;
  for (const std::vector<Index>& triangle : written.faces) {
    ASSERT_EQ(triangle.size(), 3u);
    for (Index v : triangle) ASSERT_LT(v, mesh.vertex_count());
    const Eigen::Vector3d a = mesh.position(triangle[0]);
    const Eigen::Vector3d n = (mesh.position(triangle[1]) - a).cross(mesh.position(triangle[2]) - a);
    area += 0.5 * n.norm();
    // Counter-clockwise from outside: the normal points away from the centre.
    EXPECT_GT(n.dot(a), 0.0);
    covered.insert(std::set<Index>(triangle.begin(), triangle.end()));
  }
  EXPECT_EQ(covered.size(), 12u);  // no triangle written twice
  EXPECT_DOUBLE_EQ(area, 2 * (2 * 4 + 2 * 6 + 4 * 6));
}

TEST(WriteObj, PointHullHasVerticesOnly) {
  HalfEdgeMesh mesh;
  mesh.vertices.push_back(Vertex{Eigen::Vector3d(1, 2, 3)});
  std::ostringstream out;
  write_obj(mesh, out, true);
  EXPECT_EQ(out.str(), "# hedra convex hull: 1 vertices, 0 triangles\nv 1 2 3\n");
}

}  // namespace
}  // namespace hedra::hull
