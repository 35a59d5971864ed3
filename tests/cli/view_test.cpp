// Tests of `hedra view` (tools/cli/view/):
//   * tessellation: every shape's drawn mesh is inscribed in the shape and
//     tight against it (support values over many directions, within the
//     tessellation's own error bound), in the pose's frame, margins included;
//   * the HTML page: self-contained (no external script or style), names
//     cannot break out of the data block, absent values are null;
//   * the command: `hedra view --hull` writes a page, errors exit 2 and leave
//     nothing behind; a continuous scene's page holds each moving body at its
//     start, its end and the time of impact, and each ray with its hit;
//   * in a browser: the --hull page of tools/cli/data/demo_points.xyz, a
//     synthetic scene (bodies of every shape kind, queries answered by
//     hedra::collision) and two continuous scenes (a turning bar's toi, rays)
//     open in headless Chromium without JavaScript errors,
//     report ready, and draw a viewport that is not blank
//     (view_browser_check.py). Skipped when Chromium is not installed; a
//     page that draws nothing and throws must fail the same check.
// Set HEDRA_VIEW_TEST_KEEP=DIR to keep the pages and screenshots in DIR.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <hedra/collision/detail/support.hpp>
#include <hedra/collision/query.hpp>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "cli/view/tessellate.hpp"
#include "cli/view/view_html.hpp"
#include "cli/view/view_model.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using namespace hedra;
using tool::view::PolygonMesh;
using tool::view::ViewModel;

constexpr double kPi = 3.14159265358979323846;

// ---- helpers ----------------------------------------------------------------

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::size_t count(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

struct RunResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs argv[0] (searched on PATH) with stdout and stderr captured.
RunResult run(const std::vector<std::string>& args, const fs::path& scratch) {
  const fs::path out_path = scratch / "stdout.txt", err_path = scratch / "stderr.txt";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<std::string> storage = args;
  std::vector<char*> argv;
  for (std::string& arg : storage) argv.push_back(arg.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  RunResult result;
  const int spawned = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    ADD_FAILURE() << "cannot run " << args[0];
    return result;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
  }
  if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  result.out = slurp(out_path);
  result.err = slurp(err_path);
  return result;
}

class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() / ("hedra_view_" + std::string(info->test_suite_name()) + "_" + info->name() +
                                         "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// Directions spread evenly over the sphere (Fibonacci lattice) plus the six
// axis directions, where boxes and caps have their faces.
std::vector<Eigen::Vector3d> sample_directions(int n) {
  std::vector<Eigen::Vector3d> out;
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n;
    const double r = std::sqrt(1.0 - z * z);
    out.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  for (int axis = 0; axis < 3; ++axis) {
    out.push_back(Eigen::Vector3d::Unit(axis));
    out.push_back(-Eigen::Vector3d::Unit(axis));
  }
  return out;
}

// World support value of a posed shape: h(d) = d . (R s(R^T d) + t).
double support_value(const collision::Shape& shape, const collision::Pose& pose, const Eigen::Vector3d& d) {
  return d.dot(pose.apply(collision::support(shape, pose.rotation.transpose() * d)));
}

double mesh_support_value(const PolygonMesh& mesh, const Eigen::Vector3d& d) {
  double best = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& v : mesh.vertices) best = std::max(best, d.dot(v));
  return best;
}

// Checks that `mesh` is inscribed in the posed shape (no vertex beyond any
// supporting plane, up to rounding) and tight (in every direction the mesh
// reaches within `gap` of the shape's support value).
void expect_inscribed_and_tight(const PolygonMesh& mesh, const collision::Shape& shape, const collision::Pose& pose,
                                double gap, const std::string& what) {
  ASSERT_FALSE(mesh.vertices.empty()) << what;
  const double size = collision::bounding_radius(shape);
  const double rounding = 1e-12 * size + 1e-15 * pose.translation.norm();
  double worst_outside = 0.0, worst_gap = 0.0;
  for (const Eigen::Vector3d& d : sample_directions(600)) {
    const double h = support_value(shape, pose, d);
    const double m = mesh_support_value(mesh, d);
    worst_outside = std::max(worst_outside, m - h);
    worst_gap = std::max(worst_gap, h - m);
  }
  EXPECT_LE(worst_outside, rounding) << what << ": a drawn vertex lies outside the shape";
  EXPECT_LE(worst_gap, gap + rounding) << what << ": the drawing falls short of the shape";
}

// Every face index is in range, every face has >= 3 vertices, every edge
// joins two distinct vertices.
void expect_well_formed(const PolygonMesh& mesh, const std::string& what) {
  for (const auto& face : mesh.faces) {
    EXPECT_GE(face.size(), 3u) << what;
    for (std::uint32_t i : face) EXPECT_LT(i, mesh.vertices.size()) << what;
  }
  for (const auto& edge : mesh.edges) {
    EXPECT_LT(edge[0], mesh.vertices.size()) << what;
    EXPECT_LT(edge[1], mesh.vertices.size()) << what;
    EXPECT_NE(edge[0], edge[1]) << what;
  }
}

collision::Pose random_pose(std::mt19937_64& rng, double spread) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  return collision::Pose::from_quaternion(q, spread * Eigen::Vector3d(normal(rng), normal(rng), normal(rng)));
}

std::shared_ptr<const collision::ConvexPolyhedron> rock() {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 40; ++i) {
    const Eigen::Vector3d p(normal(rng), normal(rng), normal(rng));
    points.push_back(Eigen::Vector3d(0.35, 0.25, 0.2).cwiseProduct(p.normalized()) + Eigen::Vector3d(5, -3, 2));
  }
  const collision::ConvexPolyhedron::BuildResult built = collision::ConvexPolyhedron::build(points);
  EXPECT_TRUE(built.ok()) << built.message;
  return built.polyhedron;
}

// ---- tessellation -----------------------------------------------------------

TEST(ViewTessellate, BoxIsExactlyItsSixFaces) {
  const collision::Box box{Eigen::Vector3d(1.0, 2.0, 3.0), 0.0};
  const collision::Pose pose = collision::Pose::from_quaternion(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized())), Eigen::Vector3d(10, -20, 30));
  const tool::view::TessellatedShape t = tool::view::tessellate(box, pose);
  ASSERT_TRUE(t.ok()) << t.error;
  EXPECT_EQ(t.mesh.vertices.size(), 8u);
  EXPECT_EQ(t.mesh.faces.size(), 6u);
  EXPECT_EQ(t.mesh.edges.size(), 12u);
  for (const auto& face : t.mesh.faces) EXPECT_EQ(face.size(), 4u) << "coplanar triangles merged";
  for (const Eigen::Vector3d& v : t.mesh.vertices) {
    const Eigen::Vector3d local = pose.rotation.transpose() * (v - pose.translation);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(std::abs(local[k]), box.half_extents[k], 1e-12) << "a corner";
  }
  EXPECT_TRUE(t.core.vertices.empty()) << "no margin, no core drawing";
  expect_inscribed_and_tight(t.mesh, box, pose, 1e-12, "box");
}

TEST(ViewTessellate, EveryShapeIsInscribedAndTightInItsPose) {
  std::mt19937_64 rng(2024);
  const std::vector<collision::Shape> cores = {
      collision::Sphere{0.7, 0.0},        collision::Box{Eigen::Vector3d(0.5, 0.2, 0.9), 0.0},
      collision::Capsule{0.25, 0.6, 0.0}, collision::Cylinder{0.4, 0.8, 0.0},
      collision::Cone{0.5, 0.6, 0.0},     collision::Polyhedron{rock(), 0.0},
  };
  const tool::view::TessellationOptions options;  // 32 around, 16 for margins
  // Error bounds of the drawing (tessellate.hpp): a rim of 32 points misses
  // r (1 - cos(pi/32)) < 0.005 r; the 32 x 16 sphere grid misses at most
  // r (1 - cos 8 deg) < 0.01 r; the 16 x 8 margin grid m (1 - cos 16 deg) < 0.04 m.
  for (const double margin : {0.0, 0.15}) {
    for (collision::Shape shape : cores) {
      std::visit([&](auto& s) { s.margin = margin; }, shape);
      const std::string kind = tool::view::shape_kind(shape);
      double curved = 0.0;
      if (const auto* s = std::get_if<collision::Sphere>(&shape)) curved = 0.012 * s->radius;
      if (const auto* s = std::get_if<collision::Capsule>(&shape)) curved = 0.012 * s->radius;
      if (const auto* s = std::get_if<collision::Cylinder>(&shape)) curved = 0.006 * s->radius;
      if (const auto* s = std::get_if<collision::Cone>(&shape)) curved = 0.006 * s->radius;
      const double gap = curved + 0.05 * margin + 1e-12;
      for (int trial = 0; trial < 3; ++trial) {
        const collision::Pose pose = random_pose(rng, 4.0);
        const tool::view::TessellatedShape t = tool::view::tessellate(shape, pose, options);
        const std::string what = kind + " margin " + std::to_string(margin) + " trial " + std::to_string(trial);
        ASSERT_TRUE(t.ok()) << what << ": " << t.error;
        expect_well_formed(t.mesh, what);
        EXPECT_FALSE(t.mesh.faces.empty()) << what;
        expect_inscribed_and_tight(t.mesh, shape, pose, gap, what);
        if (margin > 0.0) {
          // The core drawing is the shape without its margin.
          collision::Shape core = shape;
          std::visit([](auto& s) { s.margin = 0.0; }, core);
          expect_well_formed(t.core, what + " core");
          expect_inscribed_and_tight(t.core, core, pose, curved + 1e-12, what + " core");
        } else {
          EXPECT_TRUE(t.core.vertices.empty()) << what;
        }
      }
    }
  }
}

TEST(ViewTessellate, PolyhedronIsItsOwnMergedHullMesh) {
  const auto hull = rock();
  const collision::Polyhedron poly{hull, 0.0};
  const collision::Pose pose = collision::Pose::from_translation(Eigen::Vector3d(1, 2, 3));
  const tool::view::TessellatedShape t = tool::view::tessellate(poly, pose);
  ASSERT_TRUE(t.ok()) << t.error;
  EXPECT_EQ(t.mesh.vertices.size(), hull->vertex_count());
  EXPECT_EQ(t.mesh.faces.size(), hull->mesh().face_count());
  EXPECT_EQ(t.mesh.edges.size(), hull->mesh().edge_count());
  for (std::size_t i = 0; i < hull->vertex_count(); ++i) {
    EXPECT_TRUE(t.mesh.vertices[i].isApprox(
        hull->vertex(static_cast<hull::Index>(i)) + hull->offset() + pose.translation, 1e-14));
  }
}

TEST(ViewTessellate, FarFromTheOriginKeepsItsShape) {
  // The hull is taken in the local frame: a translation of 1e6 must not
  // coarsen a 0.1-sized capsule.
  const collision::Capsule capsule{0.02, 0.05, 0.0};
  const collision::Pose pose = collision::Pose::from_translation(Eigen::Vector3d(1e6, -1e6, 1e6));
  const tool::view::TessellatedShape t = tool::view::tessellate(capsule, pose);
  ASSERT_TRUE(t.ok()) << t.error;
  EXPECT_GT(t.mesh.faces.size(), 100u) << "still a finely drawn capsule";
  expect_inscribed_and_tight(t.mesh, capsule, pose, 0.012 * capsule.radius, "far capsule");
}

TEST(ViewTessellate, DegenerateShapesDrawAsPointsAndSegments) {
  const tool::view::TessellatedShape point = tool::view::tessellate(collision::Box{}, collision::Pose{});
  ASSERT_TRUE(point.ok()) << point.error;
  EXPECT_EQ(point.mesh.vertices.size(), 1u);
  EXPECT_TRUE(point.mesh.faces.empty());
  const tool::view::TessellatedShape segment =
      tool::view::tessellate(collision::Box{Eigen::Vector3d(0, 0, 1), 0.0}, collision::Pose{});
  ASSERT_TRUE(segment.ok()) << segment.error;
  EXPECT_EQ(segment.mesh.vertices.size(), 2u);
  ASSERT_EQ(segment.mesh.edges.size(), 1u) << "a segment is drawn as its edge";
}

TEST(ViewTessellate, InvalidShapesAndPosesAreReported) {
  const tool::view::TessellatedShape negative = tool::view::tessellate(collision::Sphere{-1.0, 0.0}, {});
  EXPECT_FALSE(negative.ok());
  EXPECT_TRUE(negative.mesh.vertices.empty());
  collision::Pose bad;
  bad.translation.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(tool::view::tessellate(collision::Sphere{1.0, 0.0}, bad).ok());
  tool::view::ViewBody body;
  std::string error;
  EXPECT_FALSE(tool::view::make_view_body("ball", collision::Sphere{-1.0, 0.0}, {}, body, error));
  EXPECT_NE(error.find("body ball"), std::string::npos) << error;
}

// ---- a synthetic scene --------------------------------------------------------

// Bodies of every shape kind and queries answered by hedra::collision: the
// crate sinks 0.02 into the ground, so its bottom face's four corners are the
// exact contact manifold of that pair (depth 0.02 each).
ViewModel demo_scene() {
  struct Body {
    std::string name;
    collision::Shape shape;
    collision::Pose pose;
  };
  const auto turn = [](double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& at) {
    return collision::Pose::from_quaternion(Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized())), at);
  };
  std::vector<Eigen::Vector3d> rock_points;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int i = 0; i < 30; ++i) {
    const Eigen::Vector3d p(normal(rng), normal(rng), normal(rng));
    rock_points.push_back(Eigen::Vector3d(0.35, 0.3, 0.25).cwiseProduct(p.normalized()));
  }
  const auto rock_hull = collision::ConvexPolyhedron::build(rock_points).polyhedron;
  const std::vector<Body> bodies = {
      {"ground", collision::Box{Eigen::Vector3d(1.6, 1.6, 0.1), 0.0}, turn(0, {0, 0, 1}, {0, 0, -0.1})},
      {"crate", collision::Box{Eigen::Vector3d(0.4, 0.4, 0.4), 0.0}, turn(0.35, {0, 0, 1}, {0, 0, 0.38})},
      {"ball", collision::Sphere{0.3, 0.0}, turn(0, {0, 0, 1}, {1.05, 0.35, 0.55})},
      {"pill", collision::Capsule{0.15, 0.3, 0.0}, turn(kPi / 2, {1, 0, 0}, {-0.95, 0.55, 0.35})},
      {"can", collision::Cylinder{0.25, 0.3, 0.06}, turn(0.2, {1, 1, 0}, {0.35, -1.05, 0.42})},
      {"tip", collision::Cone{0.3, 0.35, 0.0}, turn(0, {0, 0, 1}, {-0.9, -0.85, 0.33})},
      {"rock", collision::Polyhedron{rock_hull, 0.0}, turn(0.5, {0, 1, 1}, {0.55, 0.55, 1.25})},
  };
  ViewModel model;
  model.title = "synthetic scene (view test)";
  model.notes.push_back("queries answered by hedra::collision; the crate-ground contacts are exact by construction");
  for (const Body& b : bodies) {
    tool::view::ViewBody body;
    std::string error;
    EXPECT_TRUE(tool::view::make_view_body(b.name, b.shape, b.pose, body, error)) << error;
    model.bodies.push_back(std::move(body));
  }
  const auto add_distance = [&](int a, int b) {
    const collision::DistanceResult r =
        collision::distance(bodies[a].shape, bodies[a].pose, bodies[b].shape, bodies[b].pose);
    tool::view::ViewQuery q;
    q.a = bodies[a].name;
    q.b = bodies[b].name;
    q.type = "distance";
    q.status = collision::to_string(r.status);
    q.intersecting = r.intersecting;
    q.distance = r.distance;
    if (!r.intersecting) {
      q.point_a = r.point_a;
      q.point_b = r.point_b;
      q.normal = r.normal;
    }
    model.queries.push_back(q);
  };
  const auto add_penetration = [&](int a, int b, const char* type) {
    const collision::PenetrationResult r =
        collision::penetration(bodies[a].shape, bodies[a].pose, bodies[b].shape, bodies[b].pose);
    tool::view::ViewQuery q;
    q.a = bodies[a].name;
    q.b = bodies[b].name;
    q.type = type;
    q.status = collision::to_string(r.status);
    q.intersecting = r.intersecting;
    q.distance = r.distance;
    q.point_a = r.point_a;
    q.point_b = r.point_b;
    q.normal = r.normal;
    model.queries.push_back(q);
  };
  add_distance(1, 2);  // crate - ball
  add_penetration(0, 1, "contact");
  for (int corner = 0; corner < 4; ++corner) {  // the crate's bottom face, 0.02 below the ground's top
    const Eigen::Vector3d local((corner & 1 ? 0.4 : -0.4), (corner & 2 ? 0.4 : -0.4), -0.4);
    const Eigen::Vector3d p = bodies[1].pose.apply(local);
    model.queries.back().contacts.push_back({p, -p.z()});
  }
  add_distance(3, 1);                    // pill - crate
  add_penetration(0, 4, "penetration");  // ground - can: a hair apart, a positive signed distance
  add_distance(5, 3);                    // tip - pill
  add_distance(6, 2);                    // rock - ball
  tool::view::ViewQuery intersect;
  intersect.a = "tip";
  intersect.b = "ground";
  intersect.type = "intersect";
  const collision::IntersectResult r =
      collision::intersect(bodies[5].shape, bodies[5].pose, bodies[0].shape, bodies[0].pose);
  intersect.status = collision::to_string(r.status);
  intersect.intersecting = r.intersecting;
  model.queries.push_back(intersect);
  return model;
}

// ---- the HTML page ------------------------------------------------------------

TEST(ViewHtml, IsOneSelfContainedPage) {
  if (!tool::view::three_js_available()) GTEST_SKIP() << tool::view::three_js_missing_message();
  const std::string html = tool::view::render_view_html(demo_scene());
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("REVISION=\"111\""), std::string::npos) << "three.js r111 inlined";
  EXPECT_NE(html.find("OrbitControls"), std::string::npos);
  // Five inline scripts (error capture, data, three.js, OrbitControls,
  // viewer), none loaded from elsewhere, no stylesheet links.
  EXPECT_EQ(count(html, "<script"), 5u);
  EXPECT_EQ(count(html, "</script>"), 5u);
  EXPECT_EQ(count(html, "<script src"), 0u);
  EXPECT_EQ(count(html, "<link"), 0u);
  EXPECT_EQ(count(html, "@import"), 0u);
}

TEST(ViewHtml, DataBlockCarriesTheModelAndCannotBeBrokenOutOf) {
  if (!tool::view::three_js_available()) GTEST_SKIP() << tool::view::three_js_missing_message();
  ViewModel model;
  model.title = "<b>title</b>";
  tool::view::ViewBody body;
  std::string error;
  ASSERT_TRUE(
      tool::view::make_view_body("</script><script>alert(1)</script>", collision::Sphere{1.0, 0.0}, {}, body, error))
      << error;
  model.bodies.push_back(body);
  tool::view::ViewQuery query;
  query.a = query.b = body.name;
  query.type = "distance";
  query.status = "max_iterations";
  query.distance = std::numeric_limits<double>::quiet_NaN();  // must not reach the page as NaN
  model.queries.push_back(query);
  const std::string html = tool::view::render_view_html(model);
  EXPECT_EQ(count(html, "</script>"), 5u) << "a name must not end a script element";
  EXPECT_EQ(count(html, "<b>title</b>"), 0u) << "the title is escaped";
  const std::string open = "<script type=\"application/json\" id=\"hedra-data\">";
  const std::size_t begin = html.find(open);
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = html.find("</script>", begin);
  const nlohmann::json data = nlohmann::json::parse(html.substr(begin + open.size(), end - begin - open.size()));
  EXPECT_EQ(data["title"], "<b>title</b>");
  ASSERT_EQ(data["bodies"].size(), 1u);
  EXPECT_EQ(data["bodies"][0]["name"], body.name) << "the name survives the escaping";
  EXPECT_EQ(data["bodies"][0]["shape"], "sphere");
  EXPECT_EQ(data["bodies"][0]["mesh"]["vertices"].size(), body.mesh.vertices.size());
  EXPECT_TRUE(data["bodies"][0]["core"].is_null());
  ASSERT_EQ(data["queries"].size(), 1u);
  EXPECT_TRUE(data["queries"][0]["distance"].is_null()) << "NaN and absent values are null";
  EXPECT_TRUE(data["queries"][0]["point_a"].is_null());
  EXPECT_TRUE(data["queries"][0]["intersecting"].is_null());
  EXPECT_EQ(data["queries"][0]["status"], "max_iterations");
  EXPECT_TRUE(data["hull"].is_null());
}

// ---- the command ----------------------------------------------------------------

const std::string kDemoPoints = std::string(HEDRA_SOURCE_DIR) + "/tools/cli/data/demo_points.xyz";

TEST(ViewCli, HullPageHoldsTheHullAndItsHalfEdges) {
  if (!tool::view::three_js_available()) GTEST_SKIP() << tool::view::three_js_missing_message();
  ScratchDir dir;
  const fs::path page = dir.path() / "demo.html";
  const RunResult result = run({HEDRA_EXE, "view", "--hull", kDemoPoints, "-o", page.string()}, dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.err, "");
  EXPECT_NE(result.out.find("wrote " + page.string()), std::string::npos) << result.out;
  const std::string html = slurp(page);
  const std::string open = "id=\"hedra-data\">";
  const std::size_t begin = html.find(open) + open.size();
  const nlohmann::json hull = nlohmann::json::parse(html.substr(begin, html.find("</script>", begin) - begin))["hull"];
  ASSERT_TRUE(hull.is_object());
  EXPECT_EQ(hull["input_count"], 200);
  EXPECT_EQ(hull["input_points"].size(), 200u);
  EXPECT_EQ(hull["dimension"], 3);
  const std::size_t v = hull["vertices"].size(), f = hull["faces"].size(), e = hull["edge_count"];
  EXPECT_EQ(v + f, e + 2) << "Euler";
  ASSERT_EQ(hull["half_edges"].size(), 2 * e);
  ASSERT_EQ(hull["face_half_edges"].size(), f);
  // Each face's half-edges: in order (next), on that face, starting at its
  // polygon's vertices, twins consistent.
  const nlohmann::json& half = hull["half_edges"];  // [origin, twin, next, face]
  for (std::size_t face = 0; face < f; ++face) {
    const nlohmann::json& ring = hull["face_half_edges"][face];
    const nlohmann::json& polygon = hull["faces"][face];
    ASSERT_EQ(ring.size(), polygon.size());
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const std::size_t h = ring[k];
      EXPECT_EQ(half[h][3], face);
      EXPECT_EQ(half[h][0], polygon[k]);
      EXPECT_EQ(half[h][2], ring[(k + 1) % ring.size()]);
      EXPECT_EQ(half[half[h][1].get<std::size_t>()][1], h);
    }
  }
}

TEST(ViewCli, DefaultOutputAndStandardOutput) {
  if (!tool::view::three_js_available()) GTEST_SKIP() << tool::view::three_js_missing_message();
  ScratchDir dir;
  const RunResult piped = run({HEDRA_EXE, "view", "--hull", kDemoPoints, "-o", "-"}, dir.path());
  ASSERT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_EQ(piped.out.rfind("<!DOCTYPE html>", 0), 0u);
  // Without -o the page is the input's name with .html, in the current directory.
  const std::string script =
      "cd '" + dir.path().string() + "' && '" + HEDRA_EXE + "' view --hull '" + kDemoPoints + "' > /dev/null";
  ASSERT_EQ(std::system(script.c_str()), 0);
  EXPECT_EQ(slurp(dir.path() / "demo_points.html"), piped.out);
}

TEST(ViewCli, BadInputExitsTwoAndLeavesNothing) {
  ScratchDir dir;
  const fs::path page = dir.path() / "page.html";
  const auto expect_bad = [&](const std::vector<std::string>& args, const std::string& needle) {
    const RunResult result = run(args, dir.path());
    EXPECT_EQ(result.exit_code, 2) << result.err;
    EXPECT_EQ(result.out, "");
    EXPECT_NE(result.err.find(needle), std::string::npos) << "stderr: " << result.err;
    EXPECT_FALSE(fs::exists(page));
  };
  expect_bad({HEDRA_EXE, "view", "-o", page.string()}, "exactly one of SCENE or --hull");
  expect_bad({HEDRA_EXE, "view", "scene.json", "--hull", kDemoPoints, "-o", page.string()},
             "exactly one of SCENE or --hull");
  if (!tool::view::three_js_available()) return;
  std::ofstream(dir.path() / "bad.xyz") << "0 0 0\n1 2\n";
  expect_bad({HEDRA_EXE, "view", "--hull", (dir.path() / "bad.xyz").string(), "-o", page.string()}, "bad.xyz:2");
  // Coordinates the hull builder refuses (spans over 1e60) are bad input, not an empty page.
  std::ofstream(dir.path() / "huge.xyz") << "0 0 0\n1e61 0 0\n0 1 0\n0 0 1\n";
  expect_bad({HEDRA_EXE, "view", "--hull", (dir.path() / "huge.xyz").string(), "-o", page.string()}, "1e60");
  expect_bad({HEDRA_EXE, "view", (dir.path() / "missing.json").string(), "-o", page.string()}, "missing.json");
  expect_bad({HEDRA_EXE, "view", "--hull", kDemoPoints, "-o", (dir.path() / "no/such/dir/page.html").string()},
             "page.html");
  // Nothing half-written beside the target either.
  for (const fs::directory_entry& entry : fs::directory_iterator(dir.path())) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
  }
}

// The scene form draws every body and every query of a scene file, with the
// names and results `hedra query` gives.
const std::string kDemoScene = std::string(HEDRA_SOURCE_DIR) + "/scenes/demo.json";

TEST(ViewCli, ScenePageHoldsEveryBodyAndQuery) {
  if (!tool::view::three_js_available()) GTEST_SKIP() << tool::view::three_js_missing_message();
  ScratchDir dir;
  const fs::path page = dir.path() / "demo.html";
  const RunResult result = run({HEDRA_EXE, "view", kDemoScene, "-o", page.string()}, dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const std::string html = slurp(page);
  const std::string open = "id=\"hedra-data\">";
  const std::size_t begin = html.find(open) + open.size();
  const nlohmann::json data = nlohmann::json::parse(html.substr(begin, html.find("</script>", begin) - begin));
  const nlohmann::json scene = nlohmann::json::parse(slurp(kDemoScene));
  ASSERT_EQ(data["bodies"].size(), scene["bodies"].size());
  for (const nlohmann::json& body : data["bodies"]) {
    EXPECT_TRUE(scene["bodies"].contains(body["name"].get<std::string>())) << body["name"];
    EXPECT_FALSE(body["mesh"]["vertices"].empty()) << body["name"];
  }
  ASSERT_EQ(data["queries"].size(), scene["queries"].size());
  const RunResult query = run({HEDRA_EXE, "query", kDemoScene, "--json"}, dir.path());
  ASSERT_EQ(query.exit_code, 0) << query.err;
  const nlohmann::json answers = nlohmann::json::parse(query.out)["results"];
  ASSERT_EQ(answers.size(), data["queries"].size());
  for (std::size_t i = 0; i < answers.size(); ++i) {
    const nlohmann::json& q = data["queries"][i];
    EXPECT_EQ(q["a"], scene["queries"][i]["a"]);
    EXPECT_EQ(q["b"], scene["queries"][i]["b"]);
    EXPECT_EQ(q["type"], scene["queries"][i]["type"]);
    EXPECT_EQ(q["status"], answers[i]["status"]);
    EXPECT_EQ(q["distance"], answers[i]["distance"]) << "query " << i;
    EXPECT_EQ(q["normal"], answers[i]["normal"]) << "query " << i;
  }
}

// A continuous scene's page: each moving body of a toi query in its three
// poses (start, end, the time of impact), placed where the motion puts it,
// and each ray with its hit point.
const std::string kBarScene = std::string(HEDRA_SOURCE_DIR) + "/scenes/continuous/rotating_bar.json";
const std::string kRayScene = std::string(HEDRA_SOURCE_DIR) + "/scenes/continuous/ray_box.json";

// The model's JSON as the page carries it.
nlohmann::json page_data(const std::string& html) {
  const std::string open = "id=\"hedra-data\">";
  const std::size_t begin = html.find(open);
  if (begin == std::string::npos) return nullptr;
  const std::size_t end = html.find("</script>", begin);
  return nlohmann::json::parse(html.substr(begin + open.size(), end - begin - open.size()), nullptr, false);
}

double lowest_z(const nlohmann::json& mesh) {
  double z = INFINITY;
  for (const nlohmann::json& v : mesh["vertices"]) z = std::min(z, v[2].get<double>());
  return z;
}

TEST(ViewCli, ContinuousScenePageHoldsTheThreePoses) {
  if (!tool::view::three_js_available()) GTEST_SKIP() << tool::view::three_js_missing_message();
  ScratchDir dir;
  const fs::path page = dir.path() / "bar.html";
  const RunResult result = run({HEDRA_EXE, "view", kBarScene, "-o", page.string()}, dir.path());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json data = page_data(slurp(page));
  ASSERT_EQ(data["queries"].size(), 4u);
  // The slow bar lands on the posts at t = 0.3625: its bottom (centre z
  // 2 - 4 t, half height 0.05) is at z = 0.5 there, 1.95 at the start and
  // -2.05 at the end (its bottom face stays horizontal as it turns about z).
  const nlohmann::json& landing = data["queries"][0];
  EXPECT_EQ(landing["type"], "toi");
  EXPECT_EQ(landing["hit"], true);
  ASSERT_EQ(landing["sweeps"].size(), 1u) << "only the bar moves";
  const nlohmann::json& sweep = landing["sweeps"][0];
  EXPECT_EQ(sweep["body"], "slow");
  for (const char* pose : {"start", "end", "at_fraction"}) EXPECT_EQ(sweep[pose]["faces"].size(), 6u) << pose;
  EXPECT_NEAR(lowest_z(sweep["start"]), 1.95, 1e-12);
  EXPECT_NEAR(lowest_z(sweep["end"]), -2.05, 1e-12);
  EXPECT_NEAR(lowest_z(sweep["at_fraction"]), 0.5, 1e-9);
  const nlohmann::json& passing = data["queries"][2];
  EXPECT_EQ(passing["hit"], false);
  ASSERT_EQ(passing["sweeps"].size(), 1u);
  EXPECT_NEAR(lowest_z(passing["sweeps"][0]["at_fraction"]), -2.05, 1e-12) << "no hit: drawn at the end";
  EXPECT_TRUE(passing["point_a"].is_null());

  const fs::path ray_page = dir.path() / "ray.html";
  ASSERT_EQ(run({HEDRA_EXE, "view", kRayScene, "-o", ray_page.string()}, dir.path()).exit_code, 0);
  const nlohmann::json rays = page_data(slurp(ray_page));
  ASSERT_EQ(rays["queries"].size(), 4u);
  const nlohmann::json& ray = rays["queries"][0]["ray"];
  ASSERT_TRUE(ray.is_object());
  EXPECT_EQ(ray["origin"], nlohmann::json::array({-3.0, 0.5, 0.25}));
  EXPECT_EQ(ray["end"], nlohmann::json::array({7.0, 0.5, 0.25}));
  EXPECT_EQ(ray["hit_point"], nlohmann::json::array({1.0, 0.5, 0.25}));
  EXPECT_TRUE(rays["queries"][2]["ray"]["hit_point"].is_null()) << "a miss has no hit point";
}

// ---- in a browser ---------------------------------------------------------------

constexpr int kSkip = 77;

// Runs view_browser_check.py on `page`; skips the test when Chromium is
// missing. Returns the checker's exit code and puts its output in *output.
int browser_check(const fs::path& page, const std::vector<std::string>& options, const fs::path& scratch,
                  std::string* output) {
  std::vector<std::string> args = {HEDRA_PYTHON3, std::string(HEDRA_SOURCE_DIR) + "/tests/cli/view_browser_check.py",
                                   page.string()};
  if (!fs::exists(HEDRA_PYTHON3)) {
    *output = "SKIP: python3 was not found at configure time";
    return kSkip;
  }
  args.insert(args.end(), options.begin(), options.end());
  if (const char* keep = std::getenv("HEDRA_VIEW_TEST_KEEP")) {
    fs::create_directories(keep);
    fs::copy_file(page, fs::path(keep) / page.filename(), fs::copy_options::overwrite_existing);
    args.push_back("--screenshot=" + (fs::path(keep) / page.filename()).replace_extension(".png").string());
  }
  const RunResult result = run(args, scratch);
  *output = result.out + result.err;
  return result.exit_code;
}

TEST(ViewBrowser, HullPageRendersWithoutErrors) {
  if (!tool::view::three_js_available()) GTEST_SKIP() << tool::view::three_js_missing_message();
  ScratchDir dir;
  const fs::path page = dir.path() / "demo_points.html";
  const RunResult written = run({HEDRA_EXE, "view", "--hull", kDemoPoints, "-o", page.string()}, dir.path());
  ASSERT_EQ(written.exit_code, 0) << written.err;
  const nlohmann::json data = page_data(slurp(page));
  ASSERT_TRUE(data.is_object());
  const std::size_t faces = data["hull"]["faces"].size();
  ASSERT_GT(faces, 3u);
  // '#face=3' selects face 3 on load: its half-edge table must be built too.
  std::string output;
  const int code = browser_check(
      page, {"--fragment=#face=3", "--expect=hull-faces=" + std::to_string(faces), "--expect=selected-face=3"},
      dir.path(), &output);
  if (code == kSkip) GTEST_SKIP() << output;
  EXPECT_EQ(code, 0) << output;
}

TEST(ViewBrowser, ScenePageRendersWithoutErrors) {
  if (!tool::view::three_js_available()) GTEST_SKIP() << tool::view::three_js_missing_message();
  ScratchDir dir;
  const ViewModel model = demo_scene();
  ASSERT_EQ(model.bodies.size(), 7u);
  ASSERT_EQ(model.queries.size(), 7u);
  for (const tool::view::ViewQuery& q : model.queries) EXPECT_EQ(q.status, "ok") << q.a << "-" << q.b;
  const fs::path page = dir.path() / "scene.html";
  std::ofstream(page, std::ios::binary) << tool::view::render_view_html(model);
  std::string output;
  const int code = browser_check(page, {"--expect=bodies=7", "--expect=queries=7", "--expect=selected-query=-1"},
                                 dir.path(), &output);
  if (code == kSkip) GTEST_SKIP() << output;
  EXPECT_EQ(code, 0) << output;
}

TEST(ViewBrowser, SceneFilePageRendersWithoutErrors) {
  if (!tool::view::three_js_available()) GTEST_SKIP() << tool::view::three_js_missing_message();
  ScratchDir dir;
  const fs::path page = dir.path() / "demo_scene.html";
  const RunResult written = run({HEDRA_EXE, "view", kDemoScene, "-o", page.string()}, dir.path());
  ASSERT_EQ(written.exit_code, 0) << written.err;
  const nlohmann::json data = page_data(slurp(page));
  ASSERT_TRUE(data.is_object());
  std::string output;
  const int code =
      browser_check(page,
                    {"--fragment=#query=0", "--expect=bodies=" + std::to_string(data["bodies"].size()),
                     "--expect=queries=" + std::to_string(data["queries"].size()), "--expect=selected-query=0"},
                    dir.path(), &output);
  if (code == kSkip) GTEST_SKIP() << output;
  EXPECT_EQ(code, 0) << output;
}

// A continuous scene: each toi query's moving bar in three poses (12 in
// all), and a raycast scene's four rays; the first query selected on load.
TEST(ViewBrowser, ContinuousScenePagesRenderWithoutErrors) {
  if (!tool::view::three_js_available()) GTEST_SKIP() << tool::view::three_js_missing_message();
  ScratchDir dir;
  const std::vector<std::pair<std::string, std::vector<std::string>>> pages = {
      {kBarScene, {"--expect=queries=4", "--expect=sweep-poses=12", "--expect=rays=0"}},
      {kRayScene, {"--expect=queries=4", "--expect=sweep-poses=0", "--expect=rays=4"}}};
  for (const auto& [scene, expectations] : pages) {
    const fs::path page = dir.path() / (fs::path(scene).stem().string() + ".html");
    const RunResult written = run({HEDRA_EXE, "view", scene, "-o", page.string()}, dir.path());
    ASSERT_EQ(written.exit_code, 0) << written.err;
    std::vector<std::string> options = expectations;
    options.push_back("--fragment=#query=0");
    options.push_back("--expect=selected-query=0");
    std::string output;
    const int code = browser_check(page, options, dir.path(), &output);
    if (code == kSkip) GTEST_SKIP() << output;
    EXPECT_EQ(code, 0) << scene << ": " << output;
  }
}

TEST(ViewBrowser, CheckerRejectsABlankPageThatThrows) {
  // The same check must fail on a page that reports ready but draws nothing
  // and throws: otherwise the two tests above could not fail.
  ScratchDir dir;
  const fs::path page = dir.path() / "broken.html";
  std::ofstream(page) << "<!DOCTYPE html><html><body style=\"background:#f3f4f6\"><script>"
                         "document.documentElement.setAttribute('data-hedra-ready','true');"
                         "document.documentElement.setAttribute('data-hedra-errors','1');"
                         "</script><pre id=\"hedra-error-log\">error: boom</pre></body></html>";
  std::string output;
  const int code = browser_check(page, {}, dir.path(), &output);
  if (code == kSkip) GTEST_SKIP() << output;
  EXPECT_EQ(code, 1) << output;
  EXPECT_NE(output.find("JavaScript errors"), std::string::npos) << output;
  EXPECT_NE(output.find("error: boom"), std::string::npos) << output;
  EXPECT_NE(output.find("viewport is blank"), std::string::npos) << output;
}

}  // namespace
