// `hedra bench --continuous`: times of impact on seeded families of sweeps,
// hedra (time_of_impact; shape_cast on sweeps without rotation) beside the
// continuous peers (tools/peers/continuous.hpp), every answer judged against
// the exact first contact of tools/reference (exact_first_contact: the exact
// signed distance traced along the motion with a Lipschitz bound), which
// shares no code with hedra's queries.
//
// Families:
//   toi-thin-plate      small fast bodies (0.05) through a plate 1e-2 thick
//                       over a travel of 10 (1e-3 of it), straight or spinning
//   toi-grazing         passes that miss by 1e-2 .. 1e-8, touch, or cut 1e-7
//                       .. 1e-3 deep (spheres past a sphere, a sphere and a
//                       turning box over a face)
//   toi-rotating-bar    a long thin bar turning through a gap between posts
//   toi-initial-contact bodies starting overlapping, a hair inside, touching
//   toi-small-large     1e-3 bodies spinning onto a 1e3 block (both roles)
//   toi-far             the spinning thin-plate sweeps 1e4 .. 1e6 from the origin
//
// Per method and family: median time per query (ns); tunnelled (a reported
// time after the reference's late end by more than the tolerance, or a miss
// where the reference certifies a contact deeper than the tolerance), and of
// those the ones that went through (a miss, or later than 1e-3 of the size:
// a body inside the other); false hits (a hit where the pair is certainly
// apart by more than the tolerance); the largest error in distance along
// the motion (times the distance-rate bound) relative to the pair's size;
// failures (errors, crashes, timeouts); unsupported sweeps. Tolerance: 1e-9
// of the size plus 64 eps of the distance from the origin.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace hedra::tool::bench {

struct ContinuousOptions {
  std::uint64_t seed = 1;
  bool quick = false;
  std::vector<std::string> families;  // empty: all
  std::vector<std::string> methods;   // empty: all (hedra_toi always runs)
  double peer_timeout_seconds = 20.0;
  int loops = 7;
};

struct ContinuousRow {
  std::string family, method;
  int cases = 0, answered = 0, unsupported = 0, failures = 0;
  int hits = 0, tunnelled = 0, false_hits = 0;
  int through = 0;         // of the tunnelled: a miss of a certified contact, or a time later than 1e-3 of the size
  double median_ns = 0.0;  // over the answered sweeps
  double max_error = 0.0;  // distance along the motion / size
};

struct ContinuousReport {
  std::vector<ContinuousRow> rows;  // by family, then method
  // Median time of hedra_toi over the median time of bullet_f64_continuous
  // on the sweeps both answered (0 when not measured).
  double toi_over_bullet = 0.0;
  int common_sweeps = 0;
  std::vector<std::pair<std::string, double>> family_ratios;  // the same per family
  bool peers_built = false;
};

const std::vector<std::string>& continuous_family_names();
std::vector<std::string> continuous_method_names();

ContinuousReport run_continuous(const ContinuousOptions& options, std::ostream& progress);

std::string continuous_csv(const ContinuousReport& report);
std::string continuous_markdown(const ContinuousReport& report, const std::string& header);

// hedra's tunnelled, false hits and failures over every family.
int continuous_hedra_problems(const ContinuousReport& report);

}  // namespace hedra::tool::bench
