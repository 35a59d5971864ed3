// Continuous peers: the first time of contact of two moving shapes asked of
// Bullet 3.24 and FCL 0.7, beside hedra's shape_cast and time_of_impact.
// Same shapes and crash isolation as peers.hpp; motions are hedra's Sweep
// (origin linear, rotation about the shape's origin at a constant angular
// velocity), which is also Bullet's btTransformUtil integration and FCL's
// InterpMotion.
//
// Methods, in a fixed order:
//   bullet_f64_gjk_cast       btGjkConvexCast (linear: translation only)
//   bullet_f64_subsimplex     btSubsimplexConvexCast (linear: translation only)
//   bullet_f64_continuous     btContinuousConvexCollision (with rotation)
//   bullet_f32_continuous     the same, single precision
//   fcl_naive_trans           fcl::continuousCollide, CCDM_TRANS + CCDC_NAIVE
//                             (FCL's default request: 10 samples)
//   fcl_ca_trans              CCDM_TRANS + CCDC_CONSERVATIVE_ADVANCEMENT
//   fcl_ca_linear             CCDM_LINEAR (InterpMotion) + conservative
//                             advancement (with rotation)
// A translation-only method asked about a rotating sweep answers
// "unsupported" (it would ignore the rotation), as do shapes a peer lacks
// (FCL: margins; both: flat hulls) and Bullet's margins that it cannot
// keep (cones).
#pragma once

#include <functional>
#include <hedra/collision/time_of_impact.hpp>
#include <memory>
#include <string>
#include <vector>

#include "isolation.hpp"
#include "peers.hpp"

namespace hedra::peers {

struct SweepPair {
  collision::Shape a;
  collision::Sweep sweep_a;
  collision::Shape b;
  collision::Sweep sweep_b;
};

struct ToiPeerResult {
  bool supported = false;
  bool ok = false;
  bool hit = false;
  double fraction = 1.0;  // the reported time of impact in [0, 1] (1 without a hit)
  std::string status;     // "ok", or why not
  double time_ns = 0.0;   // filled by callers that time the query
};

class PreparedSweep {
 public:
  virtual ~PreparedSweep() = default;
  virtual ToiPeerResult query() = 0;
};

using PrepareSweepFunction = std::unique_ptr<PreparedSweep> (*)(const SweepPair& pair);

struct ContinuousPeerMethod {
  const char* name;
  const char* description;
  bool rotation;  // follows the sweeps' rotation (otherwise translation only)
  PrepareSweepFunction prepare;
  ToiPeerResult run(const SweepPair& pair) const { return prepare(pair)->query(); }
};

const std::vector<ContinuousPeerMethod>& continuous_peer_methods();
const ContinuousPeerMethod* find_continuous_peer_method(const std::string& name);

// run_isolated (isolation.hpp) for continuous calls.
std::vector<ToiPeerResult> run_isolated_toi(const std::function<ToiPeerResult(std::size_t)>& call, std::size_t count,
                                            const IsolationSettings& settings = {});

}  // namespace hedra::peers
