// Timing helpers of the scene runner and the subcommands that report
// `time_ns` (in the scene library so that it needs nothing of the CLI): the median
// of repeated measurements, taken with std::chrono::steady_clock (monotonic,
// so a clock adjustment never yields a negative time).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace hedra::tool {

using Clock = std::chrono::steady_clock;

inline double elapsed_ns(Clock::time_point start, Clock::time_point stop) {
  return std::chrono::duration<double, std::nano>(stop - start).count();
}

// Median of `samples` (the mean of the two middle ones for an even count);
// 0 for none. Takes a copy because it reorders.
inline double median(std::vector<double> samples) {
  if (samples.empty()) return 0.0;
  const std::size_t middle = samples.size() / 2;
  std::nth_element(samples.begin(), samples.begin() + middle, samples.end());
  const double upper = samples[middle];
  if (samples.size() % 2 == 1) return upper;
  const double lower = *std::max_element(samples.begin(), samples.begin() + middle);
  return lower + (upper - lower) / 2;
}

// A duration for a person: "850 ns", "12.3 us" or "4.5 ms".
inline std::string format_time(double ns) {
  char text[32];
  if (ns < 1e4) {
    std::snprintf(text, sizeof text, "%.0f ns", ns);
  } else if (ns < 1e7) {
    std::snprintf(text, sizeof text, "%.1f us", ns / 1e3);
  } else {
    std::snprintf(text, sizeof text, "%.1f ms", ns / 1e6);
  }
  return text;
}

}  // namespace hedra::tool
