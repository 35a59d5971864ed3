// The embedding API: queries between two posed shapes.
//
//   intersect(a, pose_a, b, pose_b)        do they overlap or touch? (GJK,
//                                          stops at the first separating axis)
//   distance(a, pose_a, b, pose_b, cache)  distance, unit normal from A toward
//                                          B and world witness points
//   penetration(a, pose_a, b, pose_b, cache) signed distance (negative =
//                                          depth), normal and witnesses in
//                                          every case: GJK, then EPA from
//                                          GJK's final simplex when the cores
//                                          overlap (epa.hpp).
//
// How a query runs: one std::visit on the pair of shapes picks fully typed
// code; each shape splits into core + radius (minkowski.hpp); B's core is
// placed in A's core frame (relative_pose), GJK runs on the cores with no
// virtual call and no allocation, and the radii are added analytically:
//   distance = core distance - r_a - r_b,
//   point_a  = core point_a + r_a n,   point_b = core point_b - r_b n,
// with n the unit normal from A toward B. Results return to world
// coordinates at the end (point_b - point_a = distance * normal up to the
// rounding of the world coordinates).
//
// penetration() runs the same GJK on the cores. Separated cores: the answer
// is GJK's, minus the radii (negative when the radii overlap), no EPA; for
// separated shapes it equals distance() whenever GJK certifies a separation
// above a thin touching band (1e-9 of the size; inside it EPA may answer
// better, see PenetrationSettings::touching_band). Overlapping or touching
// cores, or cores GJK cannot certify to be apart at all (lower bound 0):
// EPA on the cores from GJK's final simplex (overlapping cores of
// revolution: the exact meridian-section answer of revolution.hpp for
// parallel axes, the certified branch and bound of tilted_revolution.hpp
// for nearly coaxial ones; a sphere whose centre is inside a box's core:
// the nearest face in closed form, without GJK; docs/design.md, "Why
// penetration() tries what it tries"), and
//   distance = -(core depth + r_a + r_b),
//   point_a  = core point_a + r_a n,   point_b = core point_b - r_b n.
// Either way point_b - point_a = distance * normal.
//
// Threads: shapes are immutable and the per-query state lives on the stack
// or in the caller's cache, so many threads may query shared shapes, each
// with its own caches.
#pragma once

#include <Eigen/Core>
#include <hedra/collision/pose.hpp>
#include <hedra/collision/settings.hpp>
#include <hedra/collision/shapes.hpp>

namespace hedra::collision {

enum class Status {
  ok,              // outputs valid
  max_iterations,  // GJK or EPA hit its cap: outputs are the best so far, no verdict
  degenerate,      // a non-finite support point appeared
  invalid_input,   // a shape failed validate(), a pose is not Pose::valid() (not a rotation within rotation_tolerance,
                   // non-finite, beyond max_coordinate) or the pair is out of range (pair_in_range())
  polytope_full,   // EPA's fixed-capacity polytope ran out: best so far, see error_bound
  stalled,         // GJK or EPA stopped progressing (rounding) above the tolerance: best so far, see error_bound
};

const char* to_string(Status status);

// The smallest non-zero extent of a pair that queries accept, the mirror of
// max_shape_size and max_coordinate (and of hull::min_input_extent): queries
// square lengths, and squares of lengths below about 1e-154 underflow, so a
// pair that small has no trustworthy answer.
constexpr double min_pair_extent = 1e-60;

// The pair's extent is the largest of both shapes' bounding radii and the
// distance (largest coordinate) between their origins. A pair is in range
// when that extent is zero (coincident points) or at least min_pair_extent.
// Every query answers invalid_input for a pair out of range. Costs two
// bounding radii; the distance between origins only when both are tiny.
bool pair_in_range(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b);

struct IntersectResult {
  Status status = Status::ok;
  bool intersecting = false;  // meaningful only when status == ok
  int iterations = 0;
  int support_calls = 0;  // support evaluations of the pair (A's and B's together count one)
};

struct DistanceResult {
  Status status = Status::ok;
  bool intersecting = false;  // the shapes overlap or touch (then distance = 0)
  double distance = 0.0;      // >= 0
  // Unit normal from A toward B and the closest points, world frame; valid
  // when status == ok and !intersecting (zero otherwise: penetration() is the
  // query for overlapping shapes).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();
  // Certified upper bound on (distance - true distance), from the duality gap.
  double error_bound = 0.0;
  int iterations = 0;
  int support_calls = 0;  // support evaluations of the pair (A's and B's together count one)
};

// `cache` (optional): per-pair warm start, updated by the call. Keep one per
// pair (and per thread); a cache used with another pair only costs speed.
IntersectResult intersect(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                          GjkCache* cache = nullptr, const GjkSettings& settings = {});

DistanceResult distance(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                        GjkCache* cache = nullptr, const GjkSettings& settings = {});

// Whether GJK certifies dist(A, B) > gap (gap >= 0): a separating axis with
// room to spare, found by the boolean GJK of intersect() with the margin
// grown by gap (it stops at the first such axis). false: within gap,
// undecided (the cap) or invalid input. What a broadphase runs before the
// full query on a candidate pair that is mostly apart (World::pairs).
bool separated_beyond(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b, double gap,
                      const GjkSettings& settings = {});

// ---- penetration: EPA --------------------------------------------------------

struct PenetrationSettings {
  GjkSettings gjk;
  EpaSettings epa;
  // Cores that GJK cannot certify to be farther apart than touching_band *
  // scale may be touching: EPA then also runs from GJK's simplex (with the
  // origin on or a hair outside the polytope) and its answer is kept when
  // it converged and either |v| is within the band (GJK's normal -v/|v| is
  // then mostly rounding: its angle error grows like eps scale / |v|) or its
  // certified error is smaller than GJK's (GJK's strict-decrease rule can
  // stop short near contact on curved cores).
  double touching_band = 1e-9;
};

struct PenetrationResult {
  Status status = Status::ok;
  bool intersecting = false;  // distance <= 0: the shapes overlap or touch
  // Signed distance: > 0 separated (then equal to distance()), < 0 the
  // penetration depth, the shortest translation of B along `normal` that
  // brings the shapes to touching.
  double distance = 0.0;
  // Unit normal from A toward B and witness points, world frame, with
  // point_b - point_a = distance * normal (separated and penetrating).
  // Finite whenever status is ok, max_iterations, polytope_full or stalled;
  // zero for degenerate and invalid_input.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();
  // Bound on the error of |distance| (GJK's duality gap when separated, EPA's
  // support-value gap when penetrating); exact in exact arithmetic.
  double error_bound = 0.0;
  int gjk_iterations = 0;
  int epa_iterations = 0;  // 0 when EPA did not run
  int support_calls = 0;   // support evaluations of the pair, GJK's and EPA's
  // Axes the separating-axis test measured when it gave the depth (two
  // overlapping boxes: then GJK and EPA did not run); 0 otherwise.
  int sat_axes = 0;
};

PenetrationResult penetration(const Shape& a, const Pose& pose_a, const Shape& b, const Pose& pose_b,
                              GjkCache* cache = nullptr, const PenetrationSettings& settings = {});

}  // namespace hedra::collision
