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

}  // namespace hedra::peers
