// The regression scenes (scenes/<family>/*.json and scenes/meshes/*.obj) as
// C++ data: hedra_make_scenes writes them, the scene tests check hedra's
// queries against the same expectations without going through JSON.
//
// Every scene is built from fixed numbers and seeded std::mt19937_64 streams
// (raw 64-bit output turned into doubles here: the std:: distributions are
// not portable). Mesh coordinates are printed with 6 decimals and read back
// with hedra::hull::read_points, so the points the expectations are computed
// from are exactly the ones `hedra check` reads.
//
// Expectations come from the exact reference (tools/reference/
// exact_reference.hpp), with hull shapes given by their input points (not by
// hedra's quickhull). Per query, with sd the reference's signed distance and
// tol = 1e-9 * pair size + the reference's error bound (the pair size as in
// `hedra check`: half the distance between the centres plus the larger
// bounding radius):
//   intersecting  written when |sd| > tol (otherwise touching: either answer
//                 is right);
//   distance      sd (penetration) or max(sd, 0) (distance), tolerance tol;
//   normal        penetration: when the reference's normal is unique (one
//                 facet within tol, or separated by more than tol; never for
//                 cylinders and cones, whose normal it does not certify);
//                 distance: only when separated by more than tol;
//                 angle_tolerance 1e-6 rad;
//   contact       as penetration (the signed distance, the normal when
//                 unique), except for a pair of polytopes (boxes, hulls)
//                 separated by more than tol: there contact()'s SAT
//                 separation is only a lower bound on the distance
//                 (manifold.hpp), so neither distance nor normal is
//                 expected; plus `contact_count` when the scene gives it
//                 (the catalog's author: the count the geometry determines,
//                 e.g. 4 for a box face inside a larger face, 0 when
//                 separated, with the tool's contact distance 0).
// The catalog refuses a query whose expectation would be empty.
//
// Continuous queries (scenes/continuous/: raycast, cast, toi) carry closed-
// form answers written with the scene (each description says how): `hit`
// and `fraction`, with tolerance (1e-9 * size + 64 eps * the largest start
// coordinate) / closing speed, the size being the pair size (a ray: the
// body's bounding radius) and the closing speed how fast the distance
// shrinks at the contact (the closed form's; the ray's speed along the
// normal). expect() checks every closed-form hit against the exact reference:
// the exact signed distance of the pair posed at the fraction (poses from
// Eigen's slerp, independent of hedra's Sweep) must be the target within
// that tolerance times the speed, and a ray's point must lie on the surface.
#pragma once

#include <Eigen/Core>
#include <exact_reference.hpp>
#include <hedra/collision/detail/minkowski.hpp>
#include <hedra/collision/shapes.hpp>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace hedra::scenes {

// A generated mesh file scenes/meshes/<name>.obj.
struct Mesh {
  std::string name;                     // file stem
  std::string text;                     // the file's contents
  std::vector<Eigen::Vector3d> points;  // as read back from `text`
};

struct ShapeSpec {
  std::string name;
  std::string type;  // sphere, box, capsule, cylinder, cone, hull
  double radius = 0.0;
  double half_length = 0.0;
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();
  double margin = 0.0;
  std::vector<Eigen::Vector3d> points;  // hull: inline points, or the mesh's points
  std::string mesh;                     // hull from scenes/meshes/<mesh>.obj (empty: inline points)
};

struct BodySpec {
  std::string name;
  std::string shape;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector4d orientation{1, 0, 0, 0};         // [w, x, y, z] as written
  std::optional<Eigen::Vector3d> end_position;     // continuous queries
  std::optional<Eigen::Vector4d> end_orientation;  // [w, x, y, z] as written
};

struct QuerySpec {
  std::string a, b;                  // raycast: a is the body, b empty
  std::string type;                  // intersect, distance, penetration, contact, raycast, cast, toi
  std::optional<int> contact_count;  // contact: the number of points the geometry determines
  // Continuous queries: the ray (raycast), the target distance (cast, toi),
  // and the closed-form answer with the closing speed at the contact.
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();
  double max_fraction = 1.0;
  double target_distance = 0.0;
  bool hit = false;
  double fraction = 1.0;
  double closing_speed = 0.0;
  bool continuous() const { return type == "raycast" || type == "cast" || type == "toi"; }
};

struct SceneSpec {
  std::string family;  // the directory under scenes/
  std::string name;    // file stem and the scene's "name"
  std::string description;
  std::vector<ShapeSpec> shapes;
  std::vector<BodySpec> bodies;
  std::vector<QuerySpec> queries;

  const ShapeSpec& shape(const std::string& name) const;
  const BodySpec& body(const std::string& name) const;
};

struct Expectation {
  std::optional<bool> intersecting;
  std::optional<double> distance;
  std::optional<Eigen::Vector3d> normal;
  std::optional<int> contact_count;
  std::optional<bool> hit;         // continuous queries
  std::optional<double> fraction;  // continuous queries (tolerance: on the fraction)
  double tolerance = 0.0;
  double angle_tolerance = 0.0;
  reference::ExactResult exact;  // what the expectation came from
  double pair_size = 0.0;
};

// The meshes, then the scenes (which use the meshes' points).
std::vector<Mesh> make_meshes();
std::vector<SceneSpec> make_scenes(const std::vector<Mesh>& meshes);

// The hedra shape and pose of a body (the pose normalised as `hedra` does:
// divided by the largest component, then normalised).
collision::Shape build_shape(const ShapeSpec& spec);
collision::Pose build_pose(const BodySpec& body);
double pair_size(const collision::Shape& a, const collision::Pose& pose_a, const collision::Shape& b,
                 const collision::Pose& pose_b);

// The expectation of one query (exact.ok false: the reference failed, see
// exact.reason).
Expectation expect(const SceneSpec& scene, const QuerySpec& query);

// Runs the query through hedra::collision and compares it with `e`; returns
// an empty string when it agrees, otherwise what differs. A contact query
// (collision::contact(), default settings as in `hedra check`) also compares
// its point count and, when a distance is expected and points were found,
// the deepest point's depth with -distance (same tolerance).
std::string check_hedra(const SceneSpec& scene, const QuerySpec& query, const Expectation& e);

}  // namespace hedra::scenes
