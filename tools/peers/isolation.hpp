// Crash isolation for peer calls: run_isolated() runs a batch of calls in a
// fork()ed child and reads each result back through a pipe as soon as it is
// made. A child that dies (abort, segfault) or stays silent longer than the
// per-call timeout loses only the call it was in: that call is reported as
// `crashed` (with the signal) or `timeout`, the child is reaped, and a fresh
// child continues with the next call. The caller never sees the crash.
//
// Cost: one fork per batch (plus one per failure), so batch many calls.
// The child inherits a copy of the caller's memory (the shapes), writes only
// to the pipe and leaves with _exit (no atexit handlers, no flushed stdio
// buffers twice).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "peers.hpp"

namespace hedra::peers {

struct IsolationSettings {
  double timeout_seconds = 5.0;  // per call, measured from the previous answer
};

// Runs call(0) ... call(count - 1), each in a child process; results in order.
std::vector<PeerResult> run_isolated(const std::function<PeerResult(std::size_t)>& call, std::size_t count,
                                     const IsolationSettings& settings = {});

}  // namespace hedra::peers
