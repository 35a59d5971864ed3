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

// How every subcommand times a method (hedra's queries and every peer's,
// so that their times compare): one untimed warm-up call (first-touch page
// faults, lazy initialisation, cold caches), then `repeat` calls, each timed
// alone; `time_ns` receives their median, and the last answer is returned.
// timing_note() says so in the output.
inline constexpr int kDefaultRepeat = 21;

template <class Call>
auto warm_median(int repeat, double& time_ns, Call&& call) {
  decltype(call()) result = call();  // warm-up, untimed
  std::vector<double> times;
  times.reserve(static_cast<std::size_t>(repeat > 0 ? repeat : 1));
  for (int i = 0; i < repeat || i == 0; ++i) {
    const Clock::time_point start = Clock::now();
    auto answer = call();
    const Clock::time_point stop = Clock::now();
    times.push_back(elapsed_ns(start, stop));
    result = std::move(answer);
  }
  time_ns = median(std::move(times));
  return result;
}

// "times: warm (1 untimed call first), median of 21 timed calls".
inline std::string timing_note(int repeat) {
  const int n = repeat > 0 ? repeat : 1;
  return "times: warm (1 untimed call first), median of " + std::to_string(n) +
         (n == 1 ? " timed call" : " timed calls");
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
