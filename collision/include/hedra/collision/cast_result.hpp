// What the continuous queries (raycast.hpp, cast.hpp, time_of_impact.hpp)
// answer: a status that says which verdict was reached, and for the two
// shape queries one result struct.
//
// The promise every continuous query keeps: the reported fraction is never
// later than the first contact (beyond the query's tolerance). Every step of
// every query advances only as far as a certified lower bound of the
// distance allows, so even an answer cut short by the iteration cap carries a
// safe fraction: no contact happens before it.
#pragma once

#include <Eigen/Core>

namespace hedra::collision {

enum class CastStatus {
  hit,                    // contact at `fraction` (within the tolerance)
  separated,              // no contact up to the largest fraction searched
  initially_overlapping,  // within the target at fraction 0 (a ray: starts inside)
  max_iterations,         // the cap was hit: `fraction` is safe (no contact before it), no verdict
  stalled,                // rounding stopped the iteration above the tolerance: `fraction` is safe, no verdict
  degenerate,             // a non-finite support point appeared (NaN/inf reached the shapes)
  invalid_input,  // a shape failed validate(), a pose is not Pose::valid(), a motion or ray is not finite, out of range
                  // or zero
};

inline const char* to_string(CastStatus status) {
  switch (status) {
    case CastStatus::hit:
      return "hit";
    case CastStatus::separated:
      return "separated";
    case CastStatus::initially_overlapping:
      return "initially_overlapping";
    case CastStatus::max_iterations:
      return "max_iterations";
    case CastStatus::stalled:
      return "stalled";
    case CastStatus::degenerate:
      return "degenerate";
    case CastStatus::invalid_input:
      return "invalid_input";
  }
  return "unknown";
}

// The answer of shape_cast() and time_of_impact().
struct CastResult {
  CastStatus status = CastStatus::separated;
  // status is hit or initially_overlapping.
  bool hit = false;
  bool initially_overlapping = false;
  // hit: the first t in [0, 1] at which the distance is <= the target (never
  // later than the true one beyond the tolerance); separated: 1; the cap or a
  // stall: the largest t known to be free of contact; initially_overlapping: 0.
  double fraction = 0.0;
  // The distance at `fraction` (hit: in [target, target + error_bound], an
  // upper bound; initially_overlapping: penetration()'s signed distance,
  // negative when the shapes overlap). Zero when there is no hit.
  double distance = 0.0;
  // Unit normal from A toward B and witness points at `fraction`, world
  // frame, point_b - point_a = distance * normal; zero when there is no hit.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();
  // How far to trust `distance`: hit, the true distance at `fraction` lies
  // in [distance - error_bound, distance]; initially_overlapping,
  // penetration()'s bound.
  double error_bound = 0.0;
  int iterations = 0;     // advancement steps (shape_cast: ray-cast iterations)
  int support_calls = 0;  // support evaluations of the pair
};

}  // namespace hedra::collision
