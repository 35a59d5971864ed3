// `hedra hull`: reads a point file, builds its convex hull N times with one
// reused QuickhullBuilder, and reports counts, volume, area, the largest
// distance of an input point outside the hull and the median build time
// (file reading excluded), as a readable summary or as the JSON document of
// scene-format.md; optionally writes the hull as OBJ.
//
// Order of work, so that bad input costs little and leaves nothing behind:
// read the points (errors name file and line) -> open the --out file's
// temporary (an unwritable path fails before the build) -> build -> measure
// -> commit the OBJ -> format the output. Every failure returns before
// anything reaches stdout (see command.hpp).
#include "cli/hull_command.hpp"

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <hedra/hull/mass.hpp>
#include <hedra/hull/mesh_io.hpp>
#include <hedra/hull/quickhull.hpp>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli/atomic_file.hpp"
#include "cli/cli_validators.hpp"
#include "cli/progress.hpp"
#include "scene/timing.hpp"

namespace hedra::tool {

namespace {

struct HullOptions {
  std::string input;
  bool json = false;
  int repeat = 1;
  std::string out;
  bool triangulate = false;
};

// The upper bound on --repeat keeps the timing samples (8 bytes each) small.
constexpr int kMaxRepeat = 1000000;

struct HullReport {
  std::size_t input_count = 0;
  int repeat = 0;
  double volume = 0.0;
  double area = 0.0;
  double max_outside_distance = 0.0;
  double time_ns = 0.0;
};

const char* dimension_note(int dimension) {
  switch (dimension) {
    case 0:
      return "all points coincide: the hull is a single point";
    case 1:
      return "the points are collinear: the hull is a segment";
    case 2:
      return "the points are coplanar: the hull is a flat polygon (two back-to-back faces)";
    default:
      return nullptr;
  }
}

std::string format_json(const hull::HalfEdgeMesh& mesh, const HullReport& report) {
  nlohmann::ordered_json document;
  document["vertex_count"] = mesh.vertex_count();
  document["edge_count"] = mesh.edge_count();
  document["face_count"] = mesh.face_count();
  document["volume"] = report.volume;
  document["area"] = report.area;
  document["max_outside_distance"] = report.max_outside_distance;
  document["time_ns"] = static_cast<long long>(std::llround(report.time_ns));  // whole nanoseconds, as query's
  nlohmann::ordered_json vertices = nlohmann::ordered_json::array();
  for (const hull::Vertex& vertex : mesh.vertices) {
    vertices.push_back({vertex.position.x(), vertex.position.y(), vertex.position.z()});
  }
  document["vertices"] = std::move(vertices);
  // polygons(): convex, counter-clockwise seen from outside, as documented.
  nlohmann::ordered_json faces = nlohmann::ordered_json::array();
  for (const std::vector<hull::Index>& polygon : mesh.polygons()) faces.push_back(polygon);
  document["faces"] = std::move(faces);
  return document.dump() + "\n";
}

std::string format_text(const HullOptions& options, const hull::QuickhullResult& result, const HullReport& report) {
  const hull::HalfEdgeMesh& mesh = result.mesh;
  std::string text;
  char line[256];
  auto add = [&](const char* label, const char* format, auto value) {
    int length = std::snprintf(line, sizeof line, "  %-22s", label);
    length += std::snprintf(line + length, sizeof line - static_cast<std::size_t>(length), format, value);
    text.append(line, static_cast<std::size_t>(length));
    text += '\n';
  };
  text += "convex hull of " + options.input + " (" + std::to_string(report.input_count) + " points)\n";
  add("vertices", "%zu", mesh.vertex_count());
  add("edges", "%zu", mesh.edge_count());
  add("faces", "%zu", mesh.face_count());
  add("volume", "%.10g", report.volume);
  add("area", "%.10g", report.area);
  add("max outside distance", "%.3g", report.max_outside_distance);
  add("tolerance", "%.3g", result.tolerance);
  char time[96];
  std::snprintf(time, sizeof time, "%s (median of %d build%s)", format_time(report.time_ns).c_str(), report.repeat,
                report.repeat == 1 ? "" : "s");
  add("build time", "%s", time);
  if (const char* note = dimension_note(result.dimension)) text += std::string("  note: ") + note + "\n";
  if (!options.out.empty()) text += "  wrote " + options.out + "\n";
  return text;
}

int run_hull(const HullOptions& options, std::string& out, std::ostream& err) {
  Progress progress("hedra hull");  // stderr, only for work longer than a couple of seconds
  progress.stage("reading " + options.input);
  const hull::ReadPointsResult read = hull::read_points(options.input);
  if (!read.ok()) {
    err << read.error->message() << "\n";
    return kExitBadInput;
  }
  const std::vector<Eigen::Vector3d>& points = read.points;

  std::optional<AtomicFile> out_file;
  if (!options.out.empty()) {
    std::string error;
    out_file = AtomicFile::open(options.out, error);
    if (!out_file) {
      err << error << "\n";
      return kExitBadInput;
    }
  }

  progress.stage(
      "building the hull of " + std::to_string(points.size()) + " points" + (options.repeat > 1 ? ", build" : ""),
      options.repeat > 1 ? static_cast<std::size_t>(options.repeat) : 0);
  hull::QuickhullBuilder builder;
  hull::QuickhullResult result;
  std::vector<double> times;
  times.reserve(static_cast<std::size_t>(options.repeat));
  for (int i = 0; i < options.repeat; ++i) {
    const Clock::time_point start = Clock::now();
    hull::QuickhullResult built = builder.build(points);
    const Clock::time_point stop = Clock::now();
    times.push_back(elapsed_ns(start, stop));
    result = std::move(built);  // the previous result is freed outside the timed span
    progress.advance();
    if (!result.ok()) break;
  }

  switch (result.status) {
    case hull::QuickhullStatus::ok:
      break;
    case hull::QuickhullStatus::empty_input:
    case hull::QuickhullStatus::non_finite_input:
    case hull::QuickhullStatus::out_of_range_input:
      // The reader rejects both already; kept for a builder that is stricter.
      err << options.input << ": " << result.error << "\n";
      return kExitBadInput;
    case hull::QuickhullStatus::iteration_limit:
    case hull::QuickhullStatus::topology_failure:
      err << options.input << ": internal error in the hull builder (" << hull::to_string(result.status)
          << "): " << result.error << "\nplease report this input file as a hedra bug\n";
      return kExitInternalError;
  }

  progress.stage("measuring the hull of " + std::to_string(result.mesh.vertex_count()) + " vertices against " +
                 std::to_string(points.size()) + " points");
  HullReport report;
  report.input_count = points.size();
  report.repeat = options.repeat;
  report.volume = hull::volume(result.mesh);
  report.area = hull::surface_area(result.mesh);
  report.max_outside_distance = hull::max_outside_distance(result.mesh, points);
  report.time_ns = median(times);

  if (out_file) {
    progress.stage("writing " + options.out);
    std::ostringstream obj;
    hull::write_obj(result.mesh, obj, options.triangulate);
    std::string error;
    if (!obj || !out_file->commit(obj.str(), error)) {
      err << (error.empty() ? options.out + ": cannot format the OBJ output" : error) << "\n";
      return kExitBadInput;
    }
  }

  progress.stage("formatting the output");
  out = options.json ? format_json(result.mesh, report) : format_text(options, result, report);
  return kExitOk;
}

}  // namespace

Subcommand add_hull_command(CLI::App& app) {
  auto options = std::make_shared<HullOptions>();
  CLI::App* command = app.add_subcommand("hull", "Convex hull of a point file (.xyz, .obj or .off)");
  command->add_option("input", options->input, "Point file: .xyz (x y z a line), .obj (v lines) or .off")->required();
  command->add_flag("--json", options->json, "Print the result as one JSON document");
  command->add_option("--repeat", options->repeat, "Build the hull N times and report the median build time")
      ->check(whole_number_in(1, kMaxRepeat, "repeat count"))
      ->type_name("N");
  CLI::Option* out_option =
      command->add_option("--out", options->out, "Write the hull as a Wavefront OBJ file (atomically)")
          ->type_name("FILE");
  command->add_flag("--triangulate", options->triangulate, "With --out: write triangles instead of polygons")
      ->needs(out_option);
  return Subcommand{command, [options](std::string& out, std::ostream& err) { return run_hull(*options, out, err); }};
}

}  // namespace hedra::tool
