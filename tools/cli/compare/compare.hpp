// `hedra compare`: every query of a scene answered by hedra and by the peers
// (libccd, FCL, Bullet: tools/peers/), each answer judged against the exact
// reference (tools/reference/exact_reference.hpp).
//
// Per query:
//   reference  exact_signed_distance of the posed pair (hull shapes from
//              their input points, not from hedra's quickhull), with
//              tolerance = the scene's expect.tolerance when given, else
//              the reference's error_bound + 1e-9 of the pair's size
//              (pair_size, scene.hpp), and angle tolerance = the scene's
//              expect.angle_tolerance or 1e-6 rad.
//   judge()    one answer against the reference, by what the query type
//              defines (sd = the reference's signed distance):
//                intersecting  must equal sd < 0 when |sd| > tolerance
//                              (touching within it: either answer is right);
//                distance      |d - sd| <= tolerance for penetration,
//                              |d - max(sd, 0)| for distance;
//                normal        angle <= angle tolerance, only where the
//                              reference says the normal is unique (and, for
//                              a distance query, the pair is separated by
//                              more than the tolerance).
//              Verdicts: agree; disagree; partial (the method answered the
//              boolean, which agrees, but gave no distance the query asks
//              for, e.g. libccd on separated pairs); unsupported (the method
//              cannot pose the question: never a faked answer); failed (the
//              method was asked and failed: an error, a non-finite value, a
//              crash or a timeout); no_reference (the reference failed:
//              nothing can be judged).
//   peers      called through run_isolated (one fork per batch: a peer that
//              crashes or hangs fails that call only, never the tool).
//
// Continuous queries (raycast, cast, toi) are judged against the exact
// first contact instead (reference::exact_first_contact, traced along the
// motion with a budget of kContinuousReferenceSteps evaluations; a trace that
// runs out is "reference unavailable": no_reference, not judged). A ray is a
// point (a sphere of radius 0) moving from the origin to origin + max_fraction
// direction; a cast moves the bodies at their start orientations; a toi
// follows the full motion. Every answer (hit, fraction) goes through
// reference::judge_contact, the rule of `hedra bench --continuous`, with
// tolerance = the scene's expect.tolerance (on fraction) times the rate bound
// when given, else reference::contact_tolerance (1e-9 of the size, the larger
// reach of the two shapes): tunnelled (a miss of a certain contact, or a hit
// later than it) and false hits disagree, and so does a hit earlier than the
// bracket by more than the tolerance. The peers' continuous adapters
// (tools/peers/continuous.hpp) answer under the same isolation.
//
// Exit code (compare_exit_code): 0 when hedra agrees with the reference on
// every query, 1 when it does not on some (or the reference could not be
// computed for a discrete query: nothing verified); the peers' verdicts are reported, never
// failures. Bad input (2) is decided before anything runs.
#pragma once

#include <Eigen/Core>
#include <exact_reference.hpp>
#include <first_contact.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scene/scene_runner.hpp"
#include "scene/timing.hpp"

#if defined(HEDRA_COMPARE_WITH_PEERS)
#  include <continuous.hpp>
#  include <peers.hpp>
#endif

namespace hedra::tool {

enum class Verdict { agree, disagree, partial, unsupported, failed, no_reference };
const char* to_string(Verdict verdict);

// The exact reference of one query and the tolerances it is judged with.
struct ReferenceAnswer {
  reference::ExactResult exact;
  double pair_size = 0.0;
  double tolerance = 0.0;        // absolute, on distance
  double angle_tolerance = 0.0;  // radians, on normal
  bool tolerance_from_scene = false;
  // intersecting as the reference decides it: empty when |sd| <= tolerance.
  std::optional<bool> intersecting() const;
  // Continuous queries: the first contact of the motion (tolerance is then on
  // distance along the motion, size the larger reach).
  struct Continuous {
    collision::Shape a, b;
    reference::Motion ma, mb;
    double target = 0.0;
    double fraction_scale = 1.0;  // the query's fraction = t * this (raycast: max_fraction)
    reference::FirstContact contact;
    bool available() const { return contact.ok && !contact.exhausted; }
  };
  std::optional<Continuous> continuous;
};

// The budget of the continuous reference's trace (exact distance evaluations).
constexpr int kContinuousReferenceSteps = 5000;

// What one method said about one query, whoever the method is.
struct MethodAnswer {
  std::string method;       // "hedra", or a peer method's name
  std::string description;  // one line
  bool supported = true;    // false: cannot pose the question
  bool ok = true;           // false: asked and failed
  std::string status;
  bool intersecting = false;
  std::optional<double> distance;  // signed for penetration, >= 0 for distance
  std::optional<Eigen::Vector3d> normal;
  std::optional<Eigen::Vector3d> point_a;
  std::optional<Eigen::Vector3d> point_b;
  std::optional<double> fraction;  // continuous queries: in the query's units (1 or max_fraction without a hit)
  double time_ns = 0.0;
  // Computes in single precision (Bullet's float build, the peers named
  // *_f32_*): judged at float precision (single_precision_tolerance()).
  bool single_precision = false;
};

// A float peer's default tolerances: 16 FLT_EPSILON (1.9e-6) times the
// pair's size on distances (plus the reference's bound), 16 FLT_EPSILON
// rad on normals, where double-precision methods get 1e-9 and 1e-6.
constexpr double kSinglePrecisionRelativeTolerance = 16 * 1.1920928955078125e-7;

struct Judgement {
  Verdict verdict = Verdict::no_reference;
  std::string detail;                                // why, in words ("distance 0.3 (error 0.1 > 2e-9)")
  std::optional<double> distance_error;              // |d - expected| when a distance was compared
  std::optional<double> normal_angle;                // angle to the reference's normal (rad) when compared
  std::optional<reference::ContactVerdict> contact;  // continuous queries: the shared rule's verdict
};

// One answer against the reference for a query of `type` (the rules above).
Judgement judge(QueryType type, const ReferenceAnswer& reference, const MethodAnswer& answer);

// Angle between two directions (rad), accurate at 0 and pi.
double angle_between(const Eigen::Vector3d& u, const Eigen::Vector3d& v);

struct JudgedAnswer {
  MethodAnswer answer;
  Judgement judgement;
  std::optional<double> normal_angle_to_hedra;  // peers, when both gave a normal
};

struct QueryComparison {
  std::size_t index = 0;
  ReferenceAnswer reference;
  JudgedAnswer hedra;
  std::vector<JudgedAnswer> peers;  // in peer_methods() order; empty without peers
};

struct CompareOptions {
  int repeat = kDefaultRepeat;        // timed calls per method and query after a warm-up (warm_median())
  double peer_timeout_seconds = 5.0;  // per peer call, under run_isolated
  bool with_peers = true;             // false: hedra against the reference only
};

struct CompareReport {
  const Scene* scene = nullptr;
  bool peers_built = false;  // this build has the peers (HEDRA_WITH_PEERS)
  bool peers_run = false;
  int repeat = kDefaultRepeat;  // how every method was timed (timing_note())
  std::vector<QueryComparison> queries;
};

// The exact reference of query `index`, with the tolerances above. Hull
// shapes use their input points (the scene's points or the mesh file's).
ReferenceAnswer reference_answer(const BuiltScene& built, std::size_t index);

// hedra's outcome as a MethodAnswer.
MethodAnswer hedra_answer(const QueryOutcome& outcome);

#if defined(HEDRA_COMPARE_WITH_PEERS)
// A peer's result as a MethodAnswer for a query of `type`.
MethodAnswer peer_answer(const peers::PeerMethod& method, QueryType type, const peers::PeerResult& result);

// A continuous peer's result as a MethodAnswer (fraction in the query's units).
MethodAnswer continuous_peer_answer(const peers::ContinuousPeerMethod& method, const peers::ToiPeerResult& result,
                                    double fraction_scale);

// Runs every query with hedra and with `methods` (peer_methods(), or others
// in tests) for the discrete queries and `continuous_methods`
// (continuous_peer_methods(), or others) for the continuous ones, all peer
// calls in run_isolated batches.
CompareReport compare_scene(const LoadedScene& loaded, const CompareOptions& options,
                            const std::vector<peers::PeerMethod>& methods,
                            const std::vector<peers::ContinuousPeerMethod>& continuous_methods);
CompareReport compare_scene(const LoadedScene& loaded, const CompareOptions& options,
                            const std::vector<peers::PeerMethod>& methods);
#endif

// Runs every query with hedra and the peers of this build (none when the
// peers are not built or options.with_peers is false).
CompareReport compare_scene(const LoadedScene& loaded, const CompareOptions& options);

// 0 when hedra agrees with the reference on every query (a continuous query
// whose reference is unavailable is not judged), else 1.
int compare_exit_code(const CompareReport& report);

std::string format_compare_text(const CompareReport& report);
std::string format_compare_json(const CompareReport& report);

}  // namespace hedra::tool
