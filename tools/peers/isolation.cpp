// run_isolated: see isolation.hpp. Results travel as fixed-size records of
// plain data (smaller than PIPE_BUF, so each write is atomic); a short read
// followed by end of file means the child died inside a call.
#include "isolation.hpp"

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

namespace hedra::peers {
namespace {

struct WireResult {
  std::uint8_t supported, ok, intersecting, has_distance;
  double distance, time_ns;
  double normal[3], point_a[3], point_b[3];
  char status[160];
};
static_assert(sizeof(WireResult) < 512, "one atomic pipe write per result");

WireResult encode(const PeerResult& r) {
  WireResult w{};
  w.supported = r.supported;
  w.ok = r.ok;
  w.intersecting = r.intersecting;
  w.has_distance = r.has_distance;
  w.distance = r.distance;
  w.time_ns = r.time_ns;
  for (int k = 0; k < 3; ++k) {
    w.normal[k] = r.normal[k];
    w.point_a[k] = r.point_a[k];
    w.point_b[k] = r.point_b[k];
  }
  std::strncpy(w.status, r.status.c_str(), sizeof(w.status) - 1);
  return w;
}

PeerResult decode(const WireResult& w) {
  PeerResult r;
  r.supported = w.supported;
  r.ok = w.ok;
  r.intersecting = w.intersecting;
  r.has_distance = w.has_distance;
  r.distance = w.distance;
  r.time_ns = w.time_ns;
  for (int k = 0; k < 3; ++k) {
    r.normal[k] = w.normal[k];
    r.point_a[k] = w.point_a[k];
    r.point_b[k] = w.point_b[k];
  }
  r.status.assign(w.status, strnlen(w.status, sizeof(w.status)));
  return r;
}

PeerResult failure(const std::string& status) {
  PeerResult r;
  r.supported = true;
  r.ok = false;
  r.distance = NAN;
  r.status = status;
  return r;
}

bool write_all(int fd, const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

[[noreturn]] void child_main(const std::function<PeerResult(std::size_t)>& call, std::size_t first, std::size_t count,
                             int fd) {
  ::signal(SIGPIPE, SIG_DFL);
  for (std::size_t i = first; i < count; ++i) {
    const WireResult w = encode(call(i));
    if (!write_all(fd, &w, sizeof(w))) ::_exit(3);
  }
  ::_exit(0);
}

// What killed (or ended) the child, in words.
std::string describe_exit(int wait_status) {
  if (WIFSIGNALED(wait_status)) {
    const int sig = WTERMSIG(wait_status);
    return std::string("crashed: signal ") + std::to_string(sig) + " (" + strsignal(sig) + ")";
  }
  if (WIFEXITED(wait_status)) return "crashed: exited with code " + std::to_string(WEXITSTATUS(wait_status));
  return "crashed";
}

}  // namespace

std::vector<PeerResult> run_isolated(const std::function<PeerResult(std::size_t)>& call, std::size_t count,
                                     const IsolationSettings& settings) {
  std::vector<PeerResult> results(count);
  const int timeout_ms = static_cast<int>(std::clamp(settings.timeout_seconds * 1000.0, 1.0, 3.6e6));
  std::size_t next = 0;
  while (next < count) {
    int fds[2];
    if (::pipe(fds) != 0) {
      for (; next < count; ++next) results[next] = failure("crashed: pipe() failed");
      break;
    }
    const pid_t pid = ::fork();
    if (pid < 0) {
      ::close(fds[0]);
      ::close(fds[1]);
      for (; next < count; ++next) results[next] = failure("crashed: fork() failed");
      break;
    }
    if (pid == 0) {
      ::close(fds[0]);
      child_main(call, next, count, fds[1]);
    }
    ::close(fds[1]);
    bool child_reaped = false;
    // Read results until the batch ends or the child fails.
    while (next < count) {
      WireResult w{};
      std::size_t got = 0;
      bool timed_out = false, eof = false;
      while (got < sizeof(w)) {
        pollfd p{fds[0], POLLIN, 0};
        const int ready = ::poll(&p, 1, timeout_ms);
        if (ready < 0 && errno == EINTR) continue;
        if (ready == 0) {
          timed_out = true;
          break;
        }
        const ssize_t n = ::read(fds[0], reinterpret_cast<char*>(&w) + got, sizeof(w) - got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
          eof = true;
          break;
        }
        got += static_cast<std::size_t>(n);
      }
      if (got == sizeof(w)) {
        results[next++] = decode(w);
        continue;
      }
      int wait_status = 0;
      if (timed_out) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &wait_status, 0);
        results[next++] = failure("timeout: no answer within " + std::to_string(settings.timeout_seconds) + " s");
      } else if (eof) {
        ::waitpid(pid, &wait_status, 0);
        results[next++] = failure(describe_exit(wait_status));
      }
      child_reaped = true;
      break;  // a fresh child continues with the next call
    }
    ::close(fds[0]);
    if (!child_reaped) {
      int wait_status = 0;
      ::waitpid(pid, &wait_status, 0);
    }
  }
  return results;
}

}  // namespace hedra::peers
