// `hedra bench`: error against run time for hedra (at several tolerances)
// and the peers (libccd, FCL 0.7, Bullet 3.24), on the families of
// workloads.hpp, every answer judged against the exact reference.
//
// Methods:
//   hedra          collision::penetration with its default settings
//                  (GJK and EPA tolerances 1e-10, relative and absolute)
//   hedra@T        the same with every GJK and EPA tolerance set to T
//                  (T = 1e-3 .. 1e-12): hedra's own error/time curve
//   peers          every method of tools/peers (peers.hpp lists them), with
//                  their own primitives and convex-hull types, asked the
//                  same signed-distance question (PeerQuery::penetration)
//
// The question (BenchOptions::query, `--query`):
//   penetration    the above (the default): every pair, signed distance
//   distance       collision::distance (and the sweep's GJK tolerances)
//                  against PeerQuery::distance, on each family's separated
//                  pairs only (exact signed distance above the tolerance
//                  below, error bound plus fail_tolerance of the size: no
//                  touching pair), judged on the verdict, the distance and
//                  the normal as penetration is
//   intersect      collision::intersect (hedra's default only: it has no
//                  tolerance to sweep but the touching one) against
//                  PeerQuery::intersect, libccd's plain GJK (ccd_gjk,
//                  ccdGJKIntersect) included, on every pair, judged on the
//                  verdict alone: it must be the reference's sign where
//                  |sd| exceeds the tolerance; within it (touching pairs)
//                  either verdict is right
// Every method gets every case; a peer that cannot pose a case (FCL has no
// margins nor flat hulls, libccd gives no distance between separated
// shapes) says so and is counted as unsupported or partial, never faked.
//
// Timing (per case and method): one call first (its answer is the one
// judged), then `loops` timed loops of k calls each, k chosen so that a
// loop lasts about `loop_ns`; the case's time is the median over the loops
// of loop time / k. Families report the median and the 99th percentile
// (nearest rank) of those per-case times. hedra runs cold (no cache, as the
// peers do with objects prepared once outside the timing); peers run in
// forked children under a watchdog (isolation.hpp), one batch per family
// and method, so a crash or a hang costs one case, never the run.
//
// Errors (penetration and distance): absolute, |d - sd| for polytope cores
// (exact up to rounding), for curved pairs the distance from d to the
// reference's certified bracket [lower, upper];
// relative = absolute / the pair's size (the larger bounding radius, as
// `hedra compare` measures it). Normal angles where the reference says the
// normal is unique.
//
// Failures (counted per family and method): a wrong intersecting verdict
// where |sd| exceeds the tolerance; a distance error above the tolerance;
// a normal more than the angle tolerance off a unique reference normal;
// NaN or infinity; an exception, crash or timeout; an iteration or capacity
// cap (hedra's max_iterations and polytope_full, peers' error codes).
// hedra's `stalled` (rounding stopped progress) is judged by its answer,
// except under intersect, whose verdict is defined only when ok.
// Tolerances, for a method that asked for tolerance T (peers: T = 0):
//   distance  reference error bound + max(fail_tolerance, 2 T) * size
//   normal    1e-3 rad, judged only where 2 T <= fail_tolerance (a looser
//             tolerance asks for the depth only: stopping that far short,
//             GJK or EPA may end on a feature far from the true normal with
//             the distance along it within the tolerance)
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "cli/bench/workloads.hpp"
#include "cli/compare/compare.hpp"

#if defined(HEDRA_COMPARE_WITH_PEERS)
#  include <peers.hpp>
#endif

namespace hedra::tool::bench {

struct Method {
  std::string name;
  std::string description;
  bool is_hedra = false;
  double tolerance = 0.0;   // hedra: the GJK/EPA tolerance asked for; peers: 0
  bool is_default = false;  // the hedra of the default settings
#if defined(HEDRA_COMPARE_WITH_PEERS)
  const peers::PeerMethod* peer = nullptr;
#endif
};

// hedra's tolerance sweep (the default, 1e-10, is the method "hedra").
std::vector<double> hedra_tolerances(bool quick);

// The questions `--query` names: penetration, distance, intersect.
std::vector<QueryType> bench_queries();
std::optional<QueryType> find_bench_query(const std::string& name);

// Every method of this build for `query`: hedra, its sweep (not for
// intersect), then the peers (when built) that can answer it (ccd_gjk only
// for intersect: it gives no distance).
std::vector<Method> all_methods(bool quick, QueryType query = QueryType::penetration);

struct BenchOptions {
  WorkloadOptions workload;
  std::vector<std::string> families;         // empty: all
  std::vector<std::string> methods;          // empty: all
  std::string scene;                         // non-empty: this scene's queries instead of the families
  QueryType query = QueryType::penetration;  // penetration, distance or intersect
  double fail_tolerance = 1e-6;              // relative to the pair's size
  double peer_timeout_seconds = 5.0;
  int loops = 7;             // timed loops per case and method
  double loop_ns = 50000.0;  // target duration of one loop
};

struct CaseResult {
  MethodAnswer answer;
  Judgement judgement;
  double tolerance = 0.0;  // the distance tolerance applied (absolute)
  bool failure = false;
  std::string failure_kind;  // "", "classification", "error", "normal", "failed: <status>"
  std::optional<double> abs_error;
  std::optional<double> rel_error;
};

struct FamilyRun {
  std::string name;
  std::string parameter;  // the swept quantity's name, or ""
  std::vector<BenchCase> cases;
  std::size_t dropped = 0;  // no reference
  std::size_t skipped = 0;  // not asked: not separated beyond the tolerance (distance)
  std::vector<std::string> notes;
  std::vector<std::vector<CaseResult>> results;  // [method][case]
  double reference_seconds = 0.0;
};

struct Summary {
  std::size_t cases = 0;
  std::size_t supported = 0;  // cases the method could pose
  std::size_t answered = 0;   // ... and answered with a distance
  std::size_t partial = 0;    // answered the boolean only
  std::size_t failures = 0;
  std::vector<std::string> failure_kinds;      // distinct, with counts ("error x3")
  std::vector<std::string> unsupported;        // distinct reasons
  double time_median_ns = 0, time_p99_ns = 0;  // over supported cases
  double abs_median = 0, abs_p99 = 0, abs_max = 0;
  double rel_median = 0, rel_p99 = 0, rel_max = 0;
  std::optional<double> angle_median;  // rad, where the normal is unique
};
Summary summarize(const std::vector<CaseResult>& results);

struct StabilityRow {
  double parameter = 0.0;
  std::size_t cases = 0;  // answered with a distance
  std::size_t failures = 0;
  double rel_median = 0.0, rel_max = 0.0;
};
// Per distinct parameter value (ascending) of a family's cases.
std::vector<StabilityRow> stability(const FamilyRun& family, const std::vector<CaseResult>& results);

struct BenchReport {
  QueryType query = QueryType::penetration;
  std::vector<Method> methods;
  std::vector<FamilyRun> families;
  bool peers_built = false;
  double elapsed_seconds = 0.0;
};

// One case judged for one method (the failure rules above).
CaseResult judge_case(const BenchCase& c, const Method& method, MethodAnswer answer, double fail_tolerance,
                      QueryType query = QueryType::penetration);

// Whether `query` asks about the case: distance only on pairs separated
// beyond the tolerance (the reference's error bound + fail_tolerance x size).
bool asks_about(QueryType query, const BenchCase& c, double fail_tolerance);

// Keeps the cases `options.query` asks about (counted in `skipped`).
void keep_asked_cases(FamilyRun& family, const BenchOptions& options);

// Runs the families (or the scene's queries, loaded by the caller into
// `scene_cases`) with `methods`; progress lines on `progress`.
BenchReport run_bench(const BenchOptions& options, const std::vector<Method>& methods, std::vector<FamilyRun> families,
                      std::ostream& progress);

// The families' cases, generated (progress on `progress`).
std::vector<FamilyRun> generate_families(const BenchOptions& options, std::ostream& progress);

// Number of failures of hedra's methods (the exit code is 1 when non-zero).
std::size_t hedra_failures(const BenchReport& report);

}  // namespace hedra::tool::bench
