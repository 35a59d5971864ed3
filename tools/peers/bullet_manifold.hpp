// Bullet's polyhedral contact path (btPolyhedralContactClipping, see
// bullet_module.h) behind hedra's types, for the contact-manifold
// cross-checks and benchmarks. Boxes and polyhedra only; anything else is
// "unsupported". Conventions converted to hedra's: `normal` from A toward B,
// `depth` > 0 for penetration, `point` as Bullet reports it (on B for the
// clipped points).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "peers.hpp"

namespace hedra::peers {

struct PeerContactPoint {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // from A toward B
  double depth = 0.0;
};

struct PeerManifold {
  bool supported = false;
  bool separated = false;  // Bullet found a separating axis
  int total = 0;           // points Bullet reported (the first 64 are in `points`)
  std::vector<PeerContactPoint> points;
  std::string status;
};

class PreparedManifold {
 public:
  virtual ~PreparedManifold() = default;
  // Runs the query; `out` keeps its capacity between calls (benchmarks).
  virtual void query(double max_distance, PeerManifold& out) = 0;
};

// The pair prepared once (Bullet shapes with their polyhedral features).
std::unique_ptr<PreparedManifold> prepare_bullet_manifold(const PeerPair& pair, bool double_precision);

// A pair moving along a trajectory, answered by one btGjkPairDetector kept
// across frames (its cached separating axis is Bullet's warm start):
// penetration along hedra's conventions (normal from A toward B, distance
// < 0 overlapping). Any shape the Bullet adapter knows.
class MovingPair {
 public:
  virtual ~MovingPair() = default;
  // warm = false resets the cached axis first (a cold query).
  virtual PeerResult query(const collision::Pose& pose_a, const collision::Pose& pose_b, bool warm) = 0;
};

// Null when the module cannot be loaded or a shape is not supported.
std::unique_ptr<MovingPair> prepare_bullet_moving(const collision::Shape& a, const collision::Shape& b,
                                                  bool double_precision);

}  // namespace hedra::peers
