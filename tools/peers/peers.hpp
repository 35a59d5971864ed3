// Peers: the same query asked of libccd, FCL 0.7 and Bullet 3.24, through
// one adapter per peer method, so that tests, benchmarks and the tool can put
// hedra beside them. Only the adapters' .cpp files include peer headers;
// this header speaks hedra's types (Shape + Pose) and a common PeerResult.
//
// Conventions of PeerResult, whatever the peer's own: signed distance
// (> 0 separated, < 0 penetration depth), unit normal from A toward B in the
// world frame, witness points on A and B in the world frame with
// point_b - point_a = distance * normal as far as the peer reports them.
// `supported == false` means the peer cannot pose the question (no such
// shape, no margins, no distance at all): never a faked answer. `ok == false`
// means the peer was asked and failed (an error code, a non-finite value, a
// crash or a timeout under run_isolated); `status` says which in words.
//
// Peers are known to crash or hang on some inputs (see field-notes.md): call
// them through run_isolated (isolation.hpp) unless the inputs are known-easy.
#pragma once

#include <Eigen/Core>
#include <hedra/collision/detail/minkowski.hpp>
#include <hedra/collision/shapes.hpp>
#include <memory>
#include <string>
#include <vector>

namespace hedra::peers {

enum class PeerQuery {
  intersect,    // the boolean only (distance fields unset)
  distance,     // separation distance and closest points (0 when overlapping)
  penetration,  // signed distance: depth, normal and witnesses when overlapping
};

struct PeerResult {
  bool supported = false;
  bool ok = false;
  bool intersecting = false;
  double distance = 0.0;  // signed; NaN when the peer gave no distance
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();
  bool has_distance = false;  // distance (and normal, witnesses) were reported
  std::string status;         // "ok", or why not
  // Time of the query alone (ns), for callers that measure it (hedra
  // compare); the adapters leave it 0.
  double time_ns = 0.0;
};

struct PeerPair {
  collision::Shape a;
  collision::Pose pose_a;
  collision::Shape b;
  collision::Pose pose_b;
};

// A pair converted once into the peer's own objects (FCL collision objects,
// Bullet shapes and transforms, libccd callbacks), so that benchmarks time
// the query alone, as an application that keeps its peer objects would.
class PreparedPair {
 public:
  virtual ~PreparedPair() = default;
  virtual PeerResult query(PeerQuery query) = 0;
};

using PrepareFunction = std::unique_ptr<PreparedPair> (*)(const PeerPair& pair);

struct PeerMethod {
  const char* name;  // stable, used in benchmark names: "ccd_gjk_epa", "fcl_indep", ...
  const char* description;
  PrepareFunction prepare;
  // prepare + one query (tests, the tool).
  PeerResult run(const PeerPair& pair, PeerQuery query) const { return prepare(pair)->query(query); }
};

// The methods, in a fixed order:
//   ccd_gjk          libccd 2.1 GJK: the boolean only (libccd has no distance)
//   ccd_gjk_epa      libccd GJK + EPA (ccdGJKPenetration); separated pairs
//                    answer "separated" without a distance
//   ccd_mpr          libccd MPR (ccdMPRPenetration), same limits
//   fcl_libccd       FCL 0.7, solver GST_LIBCCD
//   fcl_indep        FCL 0.7, solver GST_INDEP
//       fcl::distance (signed) for separated pairs and distance queries,
//       fcl::collide's contact for overlapping pairs under `penetration`;
//       FCL's own primitives and fcl::Convex for hulls; no margins, no
//       point / segment / flat hulls (unsupported).
//   bullet_f32_gjk_epa, bullet_f64_gjk_epa
//                    Bullet 3.24 btGjkPairDetector + btGjkEpaPenetrationDepthSolver,
//                    single (libBulletCollision.so) and double precision
//                    (libBulletCollision-float64.so, BT_USE_DOUBLE_PRECISION)
//   bullet_f32_signed, bullet_f64_signed
//                    Bullet's btGjkEpaSolver2::SignedDistance (its normal is
//                    in A's local frame: rotated to world here)
// The two Bullet builds define the same symbols with different layouts, so
// each lives in its own module loaded with dlopen(RTLD_LOCAL); a module that
// fails to load makes its methods report "unsupported" with the reason.
// Every method above, in a fixed order.
const std::vector<PeerMethod>& peer_methods();
const PeerMethod* find_peer_method(const std::string& name);

}  // namespace hedra::peers
