// `hedra view`: builds a ViewModel (from a scene, or from a point file's
// hull) and writes render_view_html's page atomically (atomic_file.hpp).
//
// Order of work, as in `hedra hull`: check that three.js was embedded ->
// open the output's temporary (an unwritable path fails before any work) ->
// read and build -> render -> commit. Every failure returns exit 2 with a
// message and leaves no file behind.
#include "cli/view/view_command.hpp"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <hedra/collision/time_of_impact.hpp>
#include <hedra/hull/mass.hpp>
#include <hedra/hull/mesh_io.hpp>
#include <hedra/hull/quickhull.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/atomic_file.hpp"
#include "cli/view/tessellate.hpp"
#include "cli/view/view_html.hpp"
#include "scene/scene_runner.hpp"

namespace hedra::tool {

namespace {

struct ViewOptions {
  std::string scene;
  std::string hull_input;
  std::string out;
};

// More input points than this are drawn as an even subsample (every k-th
// point), so a page stays a few megabytes; the panel says so.
constexpr std::size_t kMaxDrawnInputPoints = 100000;

// "rock.xyz" -> "rock.html", in the current directory.
std::string default_output(const std::string& input) { return std::filesystem::path(input).stem().string() + ".html"; }

}  // namespace

namespace view {

namespace {

// The pose of a moving body at `t`: cast translates at the start
// orientation, toi follows the whole sweep (collision::pose_at).
collision::Pose pose_at(QueryType type, const BodySpec& body, double t) {
  const collision::Sweep sweep{body.pose(), body.end_pose()};
  if (type == QueryType::toi) return collision::pose_at(sweep, t);
  collision::Pose pose = sweep.start;
  pose.translation = body.position + t * (body.end_position - body.position);
  return pose;
}

// The continuous part of a query's view: the ray, or each moving body at
// its start, its end and the query's fraction. False with `error` set when
// a pose cannot be drawn.
bool add_continuous(const Scene& scene, const BuiltScene& built, const QuerySpec& spec, const QueryOutcome& outcome,
                    ViewQuery& query, std::string& error) {
  query.hit = outcome.hit;
  query.fraction = outcome.fraction;
  query.intersecting = std::nullopt;  // a continuous query answers hit instead
  if (spec.type == QueryType::raycast) {
    ViewRay ray;
    ray.origin = spec.origin;
    ray.end = spec.origin + spec.max_fraction * spec.direction;
    if (outcome.hit && outcome.point) ray.hit_point = *outcome.point;
    query.ray = ray;
    query.point_a = query.point_b = std::nullopt;
    if (!outcome.hit) query.normal = std::nullopt;
    return true;
  }
  query.initially_overlapping = outcome.initially_overlapping;
  if (!outcome.hit) query.point_a = query.point_b = query.normal = std::nullopt;
  for (std::size_t index : {spec.a, spec.b}) {
    const BodySpec& body = scene.bodies[index];
    const bool moves = body.end_position != body.position ||
                       (spec.type == QueryType::toi && !body.end_orientation.isApprox(body.orientation, 0.0));
    if (!moves || (index == spec.b && spec.b == spec.a)) continue;
    const collision::Shape& shape = *built.shapes[body.shape];
    ViewSweep sweep;
    sweep.body = body.name;
    ViewBody drawn;
    const double t = outcome.fraction;
    if (!make_view_body(body.name, shape, pose_at(spec.type, body, 0.0), drawn, error)) return false;
    sweep.start = std::move(drawn.mesh);
    if (!make_view_body(body.name, shape, pose_at(spec.type, body, 1.0), drawn, error)) return false;
    sweep.end = std::move(drawn.mesh);
    if (!make_view_body(body.name, shape, pose_at(spec.type, body, t), drawn, error)) return false;
    sweep.at_fraction = std::move(drawn.mesh);
    query.sweeps.push_back(std::move(sweep));
  }
  return true;
}

}  // namespace

// The scene is loaded with the same validation and messages as `hedra
// query`; every body's shape is built (all of them, not only those the
// queries use: the viewer draws them all) and every query runs as `hedra
// query` runs it. A continuous query also draws its ray, or each moving
// body at its start, its end and the query's fraction.
std::optional<ViewModel> build_scene_view_model(const std::string& scene_path, std::string& error) {
  const LoadSceneResult loaded = load_scene(scene_path);
  if (!loaded.ok()) {
    error = loaded.error;
    return std::nullopt;
  }
  Scene scene = *loaded.scene;
  BuildShapesResult built = build_shapes(scene, /*all_shapes=*/true);
  if (!built.ok()) {
    error = built.error;
    return std::nullopt;
  }
  expand_all_pairs(scene, *built.built);  // all pairs: each answered pair is drawn like a query
  ViewModel model;
  model.title = scene.name;
  model.description = scene.description;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodySpec& spec = scene.bodies[i];
    const std::optional<collision::Shape>& shape = built.built->shapes[spec.shape];
    ViewBody body;
    std::string why;
    if (!shape) {
      why = "body " + spec.name + ": its shape was not built";
    } else if (make_view_body(spec.name, *shape, built.built->poses[i], body, why)) {
      model.bodies.push_back(std::move(body));
      continue;
    }
    error = scene.file + ": bodies." + spec.name + ": cannot draw: " + why;
    return std::nullopt;
  }
  for (std::size_t i = 0; i < scene.queries.size(); ++i) {
    const QuerySpec& spec = scene.queries[i];
    const QueryOutcome outcome = run_query(*built.built, i);
    ViewQuery query;
    query.a = scene.bodies[spec.a].name;
    query.b = scene.bodies[spec.b].name;
    query.type = to_string(spec.type);
    query.status = outcome.status;
    if (outcome.ok()) query.intersecting = outcome.intersecting;
    query.distance = outcome.distance;
    query.point_a = outcome.point_a;
    query.point_b = outcome.point_b;
    query.normal = outcome.normal;
    for (const ContactPoint& contact : outcome.contacts) query.contacts.push_back({contact.point, contact.depth});
    if (is_continuous(spec.type) && !add_continuous(scene, *built.built, spec, outcome, query, error)) {
      error = scene.file + ": queries[" + std::to_string(i) + "]: cannot draw: " + error;
      return std::nullopt;
    }
    model.queries.push_back(std::move(query));
  }
  return model;
}

std::optional<ViewModel> build_hull_view_model(const std::string& input, std::string& error, int& exit_code) {
  exit_code = kExitBadInput;
  const hull::ReadPointsResult read = hull::read_points(input);
  if (!read.ok()) {
    error = read.error->message();
    return std::nullopt;
  }
  const std::vector<Eigen::Vector3d>& points = read.points;
  const hull::QuickhullResult result = hull::build_hull(points);
  switch (result.status) {
    case hull::QuickhullStatus::ok:
      break;
    case hull::QuickhullStatus::empty_input:
    case hull::QuickhullStatus::non_finite_input:
    case hull::QuickhullStatus::out_of_range_input:
      error = input + ": " + result.error;
      return std::nullopt;
    case hull::QuickhullStatus::iteration_limit:
    case hull::QuickhullStatus::topology_failure:
      error = input + ": internal error in the hull builder (" + std::string(hull::to_string(result.status)) +
              "): " + result.error + "\nplease report this input file as a hedra bug";
      exit_code = kExitInternalError;
      return std::nullopt;
  }
  const hull::HalfEdgeMesh& mesh = result.mesh;

  ViewModel model;
  model.title = "convex hull of " + std::filesystem::path(input).filename().string();
  ViewHull hull_view;
  hull_view.input = input;
  hull_view.input_count = points.size();
  const std::size_t stride = (points.size() + kMaxDrawnInputPoints - 1) / kMaxDrawnInputPoints;
  hull_view.input_points.reserve(points.size() / stride + 1);
  for (std::size_t i = 0; i < points.size(); i += stride) hull_view.input_points.push_back(points[i]);
  if (stride > 1) {
    model.notes.push_back("showing " + std::to_string(hull_view.input_points.size()) + " of the " +
                          std::to_string(points.size()) + " input points (one in " + std::to_string(stride) + ")");
  }
  for (const hull::Vertex& vertex : mesh.vertices) hull_view.vertices.push_back(vertex.position);
  hull_view.faces = mesh.polygons();
  hull_view.half_edges.reserve(mesh.half_edge_count());
  for (const hull::HalfEdge& e : mesh.edges) hull_view.half_edges.push_back({e.origin, e.twin, e.next, e.face});
  hull_view.face_half_edges.resize(mesh.face_count());
  for (hull::Index f = 0; f < mesh.face_count(); ++f) {
    for (hull::Index e : mesh.face_edges(f)) hull_view.face_half_edges[f].push_back(e);
  }
  hull_view.edge_count = mesh.edge_count();
  hull_view.dimension = result.dimension;
  hull_view.volume = hull::volume(mesh);
  hull_view.area = hull::surface_area(mesh);
  hull_view.max_outside_distance = hull::max_outside_distance(mesh, points);
  switch (result.dimension) {
    case 0:
      model.notes.push_back("all points coincide: the hull is a single point");
      break;
    case 1:
      model.notes.push_back("the points are collinear: the hull is a segment");
      break;
    case 2:
      model.notes.push_back("the points are coplanar: the hull is a flat polygon (two back-to-back faces)");
      break;
    default:
      break;
  }
  model.hull = std::move(hull_view);
  return model;
}

}  // namespace view

namespace {

int run_view(const ViewOptions& options, std::string& out, std::ostream& err) {
  const bool hull_mode = !options.hull_input.empty();
  if (hull_mode == !options.scene.empty()) {
    err << "hedra view: give exactly one of SCENE or --hull INPUT\nRun 'hedra view --help' for usage.\n";
    return kExitBadInput;
  }
  if (!view::three_js_available()) {
    err << "hedra view: " << view::three_js_missing_message() << "\n";
    return kExitBadInput;
  }
  const std::string& input = hull_mode ? options.hull_input : options.scene;
  const bool to_stdout = options.out == "-";
  const std::string target = options.out.empty() ? default_output(input) : options.out;

  std::optional<AtomicFile> out_file;
  if (!to_stdout) {
    std::string error;
    out_file = AtomicFile::open(target, error);
    if (!out_file) {
      err << error << "\n";
      return kExitBadInput;
    }
  }

  std::string error;
  int exit_code = kExitBadInput;
  const std::optional<view::ViewModel> model =
      hull_mode ? view::build_hull_view_model(input, error, exit_code) : view::build_scene_view_model(input, error);
  if (!model) {
    err << error << "\n";
    return exit_code;
  }

  std::string html = view::render_view_html(*model);
  if (to_stdout) {
    out = std::move(html);
    return kExitOk;
  }
  if (!out_file->commit(html, error)) {
    err << error << "\n";
    return kExitBadInput;
  }
  out = "wrote " + target;
  if (model->hull) {
    out += " (hull of " + std::to_string(model->hull->input_count) +
           " points: " + std::to_string(model->hull->vertices.size()) + " vertices, " +
           std::to_string(model->hull->faces.size()) + " faces)";
  } else {
    out +=
        " (" + std::to_string(model->bodies.size()) + " bodies, " + std::to_string(model->queries.size()) + " queries)";
  }
  out += "\n";
  return kExitOk;
}

}  // namespace

Subcommand add_view_command(CLI::App& app) {
  auto options = std::make_shared<ViewOptions>();
  CLI::App* command = app.add_subcommand(
      "view",
      "Write a self-contained HTML page showing a scene (bodies, closest points, normals, contacts) or, "
      "with --hull, a convex hull (points, faces, half-edges)");
  command->add_option("scene", options->scene, "Scene file (JSON, see the README)")->type_name("SCENE");
  command->add_option("--hull", options->hull_input, "Show the convex hull of a point file (.xyz, .obj or .off)")
      ->type_name("INPUT");
  command
      ->add_option("-o,--out", options->out,
                   "Output HTML file (written atomically; default: the input's name with .html, in the current "
                   "directory; '-' for standard output)")
      ->type_name("FILE");
  return Subcommand{command, [options](std::string& out, std::ostream& err) { return run_view(*options, out, err); }};
}

}  // namespace hedra::tool
