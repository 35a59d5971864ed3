// Progress on stderr for long work in the `hedra` tool: a hull of millions
// of points, a scene of thousands of queries. Never on stdout, which carries
// the result (the JSON contract of scene-format.md).
//
// A Progress object watches one command from a small thread. Work shorter
// than kQuietSeconds prints nothing, on a terminal or not, so quick commands
// and the test suite see an empty stderr. Past it, the current stage is
// printed: on a terminal as one line rewritten in place (cleared at the
// end), elsewhere (a log, a pipe) as a line when the stage changes and every
// kLogEverySeconds while it does not, e.g.
//   hedra hull: building the hull of 2000000 points (3.1 s)
//   hedra query: running queries: 5120 of 20000 (4.0 s)
// stage() takes a lock (call it between pieces of work, not inside timed
// spans); advance() is a relaxed atomic increment, cheap enough per query.
#pragma once

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

namespace hedra::tool {

class Progress {
 public:
  static constexpr double kQuietSeconds = 2.0;
  static constexpr double kLogEverySeconds = 10.0;

  // `command` prefixes every line ("hedra hull").
  explicit Progress(std::string command)
      : command_(std::move(command)),
        terminal_(isatty(STDERR_FILENO) == 1),
        start_(Clock::now()),
        thread_([this] { watch(); }) {}

  ~Progress() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
    if (terminal_ && printed_) std::fprintf(stderr, "\r\033[K");  // leave the terminal as it was
  }

  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // A new stage; `total` > 0 makes advance() count towards it.
  void stage(std::string text, std::size_t total = 0) {
    std::lock_guard<std::mutex> lock(mutex_);
    stage_ = std::move(text);
    total_ = total;
    done_.store(0, std::memory_order_relaxed);
    ++generation_;
  }

  void advance() { done_.fetch_add(1, std::memory_order_relaxed); }

 private:
  using Clock = std::chrono::steady_clock;

  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

  void watch() {
    std::unique_lock<std::mutex> lock(mutex_);
    unsigned printed_generation = 0;
    double printed_at = 0.0;
    const auto tick = std::chrono::milliseconds(terminal_ ? 250 : 500);
    while (!wake_.wait_for(lock, tick, [this] { return stop_; })) {
      const double now = seconds();
      if (now < kQuietSeconds || stage_.empty()) continue;
      const bool changed = generation_ != printed_generation;
      if (!terminal_ && !changed && now - printed_at < kLogEverySeconds) continue;
      std::string line = command_ + ": " + stage_;
      if (total_ > 0) {
        line += ": " + std::to_string(done_.load(std::memory_order_relaxed)) + " of " + std::to_string(total_);
      }
      char elapsed[32];
      std::snprintf(elapsed, sizeof elapsed, " (%.1f s)", now);
      line += elapsed;
      if (terminal_)
        std::fprintf(stderr, "\r\033[K%s", line.c_str());
      else
        std::fprintf(stderr, "%s\n", line.c_str());
      std::fflush(stderr);
      printed_ = true;
      printed_generation = generation_;
      printed_at = now;
    }
  }

  const std::string command_;
  const bool terminal_;
  const Clock::time_point start_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  bool printed_ = false;
  std::string stage_;
  std::size_t total_ = 0;
  unsigned generation_ = 0;
  std::atomic<std::size_t> done_{0};
  std::thread thread_;  // last: starts once every other member is ready
};

}  // namespace hedra::tool
