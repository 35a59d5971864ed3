// `hedra bench`'s outputs: three CSV files, a markdown report, and the
// plotting script (plot_bench.py, embedded at build time) that turns the
// CSV files into PNG and SVG figures with matplotlib.
//
//   summary.csv    one row per family and method: cases, supported,
//                  answered, partial, failures, time median / p99 (ns),
//                  absolute and relative error median / p99 / max, median
//                  normal angle (rad), hedra's requested tolerance
//   cases.csv      one row per case and method: the raw answers and errors
//   stability.csv  one row per swept family, parameter value and method:
//                  median and max relative error, failures
//   report.md      the run (date, machine, command, seed, query), a headline
//                  table (hedra beside every peer per family), hedra's time
//                  over the fastest accurate peer's per family (one that
//                  poses every case with at most 10 % failures and, except
//                  under intersect, a distance on each; under intersect also
//                  over ccd_gjk's), the per-family tables, the stability
//                  tables, what each peer could not pose, and dropped cases
// Numbers in the CSV files are plain decimal or exponent notation; an empty
// cell means "no value" (no distance answered, no unique normal).
#pragma once

#include <string>
#include <string_view>

#include "cli/bench/bench.hpp"
#include "cli/bench/plot_script.hpp"

namespace hedra::tool::bench {

struct RunInfo {
  std::string command;                  // the command line as given
  std::string date;                     // UTC, ISO 8601
  std::string machine;                  // CPU model, cores, kernel
  std::string load_before, load_after;  // /proc/loadavg's first three numbers
  std::uint64_t seed = 1;
  bool quick = false;
  std::string source;  // "families" or the scene file
};

// What the machine and the moment are (for RunInfo).
std::string machine_description();
std::string utc_now();
std::string load_average();

std::string summary_csv(const BenchReport& report);
std::string cases_csv(const BenchReport& report);
std::string stability_csv(const BenchReport& report);
std::string markdown_report(const BenchReport& report, const RunInfo& info);

}  // namespace hedra::tool::bench
