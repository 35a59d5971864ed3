// Running a scene's queries with hedra::collision: one QuerySpec -> one
// QueryOutcome, shared by `hedra query` (prints it) and `hedra check`
// (compares it with the expectation).
//
// Each query type calls exactly the library function that answers it, so
// each pays only for what it asks (scene-format.md):
//   intersect   -> collision::intersect    (boolean GJK, early exit; no EPA)
//   distance    -> collision::distance     (GJK; no EPA)
//   penetration -> collision::penetration  (GJK, then EPA only when the cores
//                                           overlap or touch)
//   contact     -> collision::contact      (SAT + clipping or the curved
//                                           paths of manifold.hpp; up to 4 points)
//   raycast     -> collision::raycast      (closed forms, or the GJK ray cast)
//   cast        -> collision::shape_cast   (translation only, start orientations)
//   toi         -> collision::time_of_impact (the full motion, rotation included)
//
// Continuous outcomes follow scene-format.md: hit, fraction (the largest
// fraction searched when there is no hit), and the vector fields zero (never
// absent) when there is none. Their status is "ok" for the library's hit,
// separated and initially_overlapping, otherwise the library's word
// (max_iterations, stalled, degenerate, invalid_input).
//
// Outcomes never hold NaN: a value the query does not define (the distance
// of an intersect query, the normal of overlapping shapes in a distance
// query, any output of a failed query) is absent (printed as JSON null),
// and a non-finite library output is dropped with status "non_finite".
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace hedra::tool {

struct ContactPoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // world frame
  double depth = 0.0;                               // > 0 penetrating, < 0 speculative
};

struct QueryOutcome {
  QueryType type = QueryType::distance;
  std::size_t body_a = 0, body_b = 0;  // indices into Scene::bodies (raycast: both the body)
  std::string status = "ok";           // collision::to_string(Status), or "non_finite"
  bool intersecting = false;
  std::optional<double> distance;          // signed for penetration and contact
  std::optional<Eigen::Vector3d> normal;   // unit, world, from A toward B
  std::optional<Eigen::Vector3d> point_a;  // world
  std::optional<Eigen::Vector3d> point_b;
  std::vector<ContactPoint> contacts;
  // Continuous queries (raycast, cast, toi).
  bool hit = false;
  double fraction = 0.0;
  bool initially_overlapping = false;    // cast, toi; a ray: started inside
  std::optional<Eigen::Vector3d> point;  // raycast: the hit point (world)
  int cast_iterations = 0;               // ray-cast iterations or advancement steps
  double error_bound = 0.0;              // the library's bound on |distance| error (0 for intersect)
  // Which stages ran (for --stats): GJK always; EPA only in penetration and
  // contact queries whose cores overlap or touch (epa_ran: EPA expanded at
  // least once, the most the library's result tells); the manifold only for
  // contact.
  int gjk_iterations = 0;
  int epa_iterations = 0;
  // Support evaluations of the pair in GJK and EPA (A's and B's count one;
  // a contact query's SAT lookups on polytopes are not counted).
  int support_calls = 0;
  // Axes the separating-axis test measured when it gave a penetration
  // query's depth (two overlapping boxes: no GJK, no EPA); 0 otherwise.
  int sat_axes = 0;
  bool epa_ran = false;
  bool manifold_ran = false;
  double time_ns = 0.0;  // median over the repetitions, excluding parsing and building
  bool ok() const { return status == "ok"; }
};

// Runs query `index` of the built scene `repeat` (>= 1) times, each time
// from a cold start (no cache), and keeps the last answer and the median time.
QueryOutcome run_query(const BuiltScene& built, std::size_t index, int repeat = 1);

// A query over all pairs ("pairs": "all"): collision::World over every body
// of the scene (body i = Scene::bodies[i], numbered in byte order of the
// names), then World::pairs with the query's type and max_distance on
// `threads` threads (0: all cores). One outcome per answered pair, sorted by
// (body_a, body_b), body_a < body_b. Each outcome's time_ns is the time of
// the whole query (adding the bodies, building the tree, the broadphase and
// every pair's query, each call from a new World), taken like every query's
// (timing.hpp, warm_median). Iteration counts are not reported (0).
struct AllPairsOutcome {
  std::vector<QueryOutcome> pairs;
  std::size_t bodies = 0;
  std::size_t candidates = 0;  // pairs whose grown boxes overlap
  double time_ns = 0.0;
};
AllPairsOutcome run_all_pairs(const BuiltScene& built, std::size_t index, int repeat = 1, int threads = 0);

// Replaces every all-pairs query of `scene` by one ordinary query per pair
// run_all_pairs answers (same type; a contact query's contact_distance is
// the max_distance), in place and in order, so that the commands that judge
// or draw pairs one at a time (compare, view, bench) see them. `built` must
// be build_shapes(scene)'s (built.scene == &scene).
void expand_all_pairs(Scene& scene, BuiltScene& built, int threads = 0);

// A scene read, checked runnable and built: what every scene command starts
// from. The Scene lives on the heap so that `built.scene` stays valid when
// the LoadedScene moves.
struct LoadedScene {
  std::unique_ptr<Scene> scene;
  BuiltScene built;
};

// load_scene + build_shapes; on failure returns nothing
// and sets `error` to the message (exit code 2).
std::optional<LoadedScene> prepare_scene(const std::string& path, std::string& error);

// The shortest text that reads back as exactly `x` ("0.1", "-2.5e-17").
std::string shortest(double x);

}  // namespace hedra::tool
