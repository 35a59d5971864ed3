// Scene files (docs/scene-format.md): JSON -> typed shapes, bodies and
// queries, then the hedra::collision shapes the queries need. Part of the
// scene library (tools/scene/, hedra_scene), which the tool, its tests, the
// scene fuzz target and the microbenchmarks link.
//
// Two steps, both returning errors as values:
//   load_scene(path)        reads and validates the whole document: every
//                           field's type, count, sign and finiteness, every
//                           reference between sections, and no unknown key
//                           (a typo must not be silently ignored; only the
//                           top-level "name" and "description" are free).
//   build_shapes(scene)     reads mesh files and builds hulls, only for the
//                           shapes some query uses (pay only for what is
//                           asked: a scene of spheres builds no hull), each
//                           shape once: bodies sharing a hull share its
//                           ConvexPolyhedron through the shared_ptr.
// Every message has the form "<file>: <JSON path>: <reason>", e.g.
//   scene.json: shapes.rock.points[3]: expected 3 numbers
//   scene.json:4:17: malformed JSON: ...        (line and column, 1-based)
//   scene.json: shapes.mesh.file: meshes/rock.obj:17: expected 3 numbers ...
// with <file> the scene path as the caller gave it.
//
// All validation lives here, so that `hedra query`, `hedra check` and
// `hedra view` reject the same files with the same words.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <hedra/collision/query.hpp>
#include <optional>
#include <string>
#include <vector>

namespace hedra::tool {

enum class ShapeKind { sphere, box, capsule, cylinder, cone, hull };
enum class QueryType { intersect, distance, penetration, contact, raycast, cast, toi };
// raycast, cast and toi: the continuous queries (a ray, or bodies moving
// from their start pose to their end pose over t in [0, 1]).
inline bool is_continuous(QueryType type) {
  return type == QueryType::raycast || type == QueryType::cast || type == QueryType::toi;
}

const char* to_string(ShapeKind kind);
const char* to_string(QueryType type);

struct ShapeSpec {
  std::string name;  // the key in "shapes"
  ShapeKind kind = ShapeKind::sphere;
  double radius = 0.0;                                     // sphere, capsule, cylinder, cone
  double half_length = 0.0;                                // capsule, cylinder, cone
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  // box
  double margin = 0.0;
  std::vector<Eigen::Vector3d> points;  // hull from "points"
  std::string file;                     // hull from a mesh "file": the path as written in the scene
  std::string resolved_file;            // ... and relative to the working directory
};

struct BodySpec {
  std::string name;                                                 // the key in "bodies"
  std::size_t shape = 0;                                            // index into Scene::shapes
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               // world frame
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // normalised
  // The pose at the end of the step (continuous queries): "end_position" and
  // "end_orientation", each defaulting to the start's.
  Eigen::Vector3d end_position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond end_orientation = Eigen::Quaterniond::Identity();  // normalised
  collision::Pose pose() const { return collision::Pose::from_quaternion(orientation, position); }
  collision::Pose end_pose() const { return collision::Pose::from_quaternion(end_orientation, end_position); }
};

struct Expectation {
  std::optional<bool> intersecting;
  std::optional<double> distance;
  std::optional<Eigen::Vector3d> normal;  // unit (normalised when read)
  std::optional<int> contact_count;
  std::optional<bool> hit;         // continuous queries only
  std::optional<double> fraction;  // continuous queries only
  // Absolute, on distance (discrete queries; default: default_tolerance())
  // or on fraction (continuous queries; default: default_fraction_tolerance()).
  std::optional<double> tolerance;
  std::optional<double> angle_tolerance;  // radians, on normal; default: kDefaultAngleTolerance
  std::optional<long long> pair_count;    // all-pairs queries only: how many pairs are answered
  bool empty() const {
    return !intersecting && !distance && !normal && !contact_count && !hit && !fraction && !pair_count;
  }
};

struct QuerySpec {
  std::size_t a = 0;  // indices into Scene::bodies (raycast: both are "body"; all pairs: unused, 0)
  std::size_t b = 0;
  // "pairs": "all": every pair of bodies within max_distance (>= 0), through
  // collision::World's broadphase (intersect, distance, penetration and
  // contact only; a contact query's contact distance is max_distance).
  bool all_pairs = false;
  double max_distance = 0.0;
  QueryType type = QueryType::distance;
  // raycast: the ray origin + t direction, t in [0, max_fraction].
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // never zero
  double max_fraction = 1.0;                            // >= 0
  double target_distance = 0.0;                         // cast, toi: >= 0
  double contact_distance = 0.0;                        // contact: >= 0, collision::ContactSettings
  std::optional<Expectation> expect;
};

struct Scene {
  std::string file;         // the path as given (used in messages)
  std::string name;         // "name", or the file's stem
  std::string description;  // may be empty
  std::vector<ShapeSpec> shapes;
  std::vector<BodySpec> bodies;
  std::vector<QuerySpec> queries;
};

struct LoadSceneResult {
  std::optional<Scene> scene;
  std::string error;  // "<file>: <path>: <reason>" when !scene
  bool ok() const { return scene.has_value(); }
};

LoadSceneResult load_scene(const std::string& path);
// The same from text in memory; `file` names it in messages and mesh files
// resolve relative to its directory.
LoadSceneResult parse_scene(const std::string& text, const std::string& file);

// The collision shapes of a scene, built lazily.
struct BuiltScene {
  const Scene* scene = nullptr;
  std::vector<std::optional<collision::Shape>> shapes;  // per ShapeSpec; empty when no query uses it
  std::vector<collision::Pose> poses;                   // per BodySpec
  std::vector<collision::Pose> end_poses;               // per BodySpec (continuous queries)
  int shapes_built = 0;
  int hulls_built = 0;
  int mesh_files_read = 0;
  double build_ns = 0.0;  // reading meshes and building hulls
};

struct BuildShapesResult {
  std::optional<BuiltScene> built;
  std::string error;  // "<file>: shapes.<name>...: <reason>" when !built
  bool ok() const { return built.has_value(); }
};

// Builds the shapes used by `scene.queries` (all of them with `all_shapes`,
// e.g. for a viewer). `scene` must outlive the result.
BuildShapesResult build_shapes(const Scene& scene, bool all_shapes = false);

// Default expectation tolerances (documented in the README):
//   distance: kDefaultRelativeTolerance * size of the pair, the size being
//   the radius of the smallest ball around the midpoint of the two shapes'
//   centres that holds both bounding balls (margins included), so it grows
//   with the shapes and with their separation, never with where they sit;
//   normal: kDefaultAngleTolerance radians.
constexpr double kDefaultRelativeTolerance = 1e-9;
constexpr double kDefaultAngleTolerance = 1e-6;
double pair_size(const collision::Shape& a, const collision::Pose& pose_a, const collision::Shape& b,
                 const collision::Pose& pose_b);
inline double default_tolerance(const collision::Shape& a, const collision::Pose& pose_a, const collision::Shape& b,
                                const collision::Pose& pose_b) {
  return kDefaultRelativeTolerance * pair_size(a, pose_a, b, pose_b);
}

// The default tolerance on a continuous query's fraction: 1e-9 of the size
// (plus the rounding of the coordinates, 64 eps times the largest start
// coordinate) measured along the motion, i.e. divided by the fastest the
// distance can change per unit of t; 1e-9 when nothing moves:
//   raycast   size = the body's bounding radius, speed = |direction|;
//   cast      size = pair_size at the start, speed = |relative translation|;
//   toi       as cast, speed = |relative translation| + theta_a r_a + theta_b r_b
//             (theta the turn of each body, r its largest reach from its origin).
double default_fraction_tolerance(const BuiltScene& built, std::size_t query);

}  // namespace hedra::tool
