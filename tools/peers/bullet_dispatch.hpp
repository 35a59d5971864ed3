// Bullet's own per-pair narrowphase behind hedra's types (bullet_dispatch.h):
// the algorithm Bullet's default dispatcher picks for the pair, run as its
// world runs it, for side-by-side benchmarks of contact().
#pragma once

#include <hedra/collision/pose.hpp>
#include <hedra/collision/shapes.hpp>
#include <memory>
#include <string>

namespace hedra::peers {

struct DispatchAnswer {
  int points = 0;        // contact points in Bullet's persistent manifold
  double deepest = 0.0;  // smallest distance among them (< 0 penetration); NaN with none
};

class DispatchedPair {
 public:
  virtual ~DispatchedPair() = default;
  // warm: the algorithm and its manifold kept from the last call; cold: made anew.
  virtual DispatchAnswer query(const collision::Pose& pose_a, const collision::Pose& pose_b, bool warm) = 0;
  // The algorithm's class, after the first query.
  virtual std::string algorithm() const = 0;
};

// Null when the module cannot be loaded or a shape is not supported (Bullet
// has every hedra shape). polyhedral: initializePolyhedralFeatures() on
// boxes and hulls.
std::unique_ptr<DispatchedPair> prepare_bullet_dispatch(const collision::Shape& a, const collision::Shape& b,
                                                        bool polyhedral, bool double_precision = true);

}  // namespace hedra::peers
