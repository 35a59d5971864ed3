// parallel_for over fixed chunks, on a job system an embedder can replace.
//
// The split: [0, count) is cut into parallel_chunk_count(count) chunks of
// nearly equal size (at most kMaxParallelChunks), a function of count alone,
// never of the thread count or of the runner. Whatever runs a chunk, and in
// whatever order, each chunk is the same range, so code that writes one
// output per row, or one output per chunk merged in chunk order, gives the
// same bits with 1, 2 or N threads.
//
// The runner: TaskRunner is the interface (Box2D's enqueueTask and Bullet's
// btITaskScheduler are the models): run(n, task, context) calls task(i,
// context) for every i in [0, n) and returns when all have returned.
// parallel_for asks it for `workers` tasks (min(threads, chunks)); each task
// takes the next chunk from a shared atomic counter until none is left, so a
// runner that runs the tasks one after another still runs every chunk.
// default_task_runner() is a persistent pool of std::threads (the calling
// thread works too); a call from inside a pool task, or while another thread
// is using the pool, runs inline on the caller instead of waiting.
//
// No allocation: the context lives on the caller's stack.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <type_traits>

namespace hedra::collision {

// A job system an embedder can replace (Box2D's enqueueTask, Bullet's btITaskScheduler are the models).
class TaskRunner {
 public:
  virtual ~TaskRunner() = default;
  virtual int concurrency() const = 0;  // how many workers may run at once (>= 1)
  // Calls task(chunk, context) once for every chunk in [0, chunk_count), possibly concurrently,
  // and returns when all have returned. Never depends on how chunks are scheduled.
  virtual void run(std::size_t chunk_count, void (*task)(std::size_t chunk, void* context), void* context) = 0;
};

// The default runner: a persistent pool of std::threads, created on first use, sized to
// std::thread::hardware_concurrency(); shared, thread-safe.
TaskRunner& default_task_runner();

struct ParallelSettings {
  int threads = 0;               // 0: all cores (the runner's concurrency); 1: run inline on the calling thread
  TaskRunner* runner = nullptr;  // nullptr: default_task_runner()
};

// The most chunks a range is cut into: enough for dynamic load balance on
// tens of cores, few enough that a chunk's bookkeeping is negligible.
inline constexpr std::size_t kMaxParallelChunks = 512;

// How many chunks [0, count) is cut into (0 for count 0): a function of count only.
inline std::size_t parallel_chunk_count(std::size_t count) { return std::min(count, kMaxParallelChunks); }

// The range [begin, end) of chunk `chunk` of [0, count): the first count % chunks
// chunks hold one row more.
struct ChunkRange {
  std::size_t begin = 0, end = 0;
};
inline ChunkRange parallel_chunk_range(std::size_t count, std::size_t chunk) {
  const std::size_t chunks = parallel_chunk_count(count);
  const std::size_t base = count / chunks, extra = count % chunks;
  const std::size_t begin = chunk * base + std::min(chunk, extra);
  return {begin, begin + base + (chunk < extra ? 1 : 0)};
}

// How many workers a call with these settings uses (>= 1).
int parallel_workers(const ParallelSettings& settings);

namespace detail {
template <class Body>
struct ParallelForContext {
  std::atomic<std::size_t> next{0};
  std::size_t count = 0;
  std::size_t chunks = 0;
  Body* body = nullptr;
  // Each task takes chunks until none is left.
  static void task(std::size_t /*worker*/, void* context) {
    auto& self = *static_cast<ParallelForContext*>(context);
    for (std::size_t chunk = self.next.fetch_add(1, std::memory_order_relaxed); chunk < self.chunks;
         chunk = self.next.fetch_add(1, std::memory_order_relaxed)) {
      const ChunkRange r = parallel_chunk_range(self.count, chunk);
      (*self.body)(chunk, r.begin, r.end);
    }
  }
};
}  // namespace detail

// body(chunk, begin, end) for every chunk of [0, count): for code that keeps
// one output per chunk (merged afterwards in chunk order).
template <class Body>
void parallel_for_chunks(std::size_t count, const ParallelSettings& settings, Body&& body) {
  const std::size_t chunks = parallel_chunk_count(count);
  if (chunks == 0) return;
  using BodyType = std::remove_reference_t<Body>;
  const std::size_t workers =
      chunks == 1 ? 1 : std::min<std::size_t>(static_cast<std::size_t>(parallel_workers(settings)), chunks);
  if (workers <= 1) {
    for (std::size_t chunk = 0; chunk < chunks; ++chunk) {
      const ChunkRange r = parallel_chunk_range(count, chunk);
      body(chunk, r.begin, r.end);
    }
    return;
  }
  detail::ParallelForContext<BodyType> context;
  context.count = count;
  context.chunks = chunks;
  context.body = &body;
  TaskRunner& runner = settings.runner ? *settings.runner : default_task_runner();
  runner.run(workers, &detail::ParallelForContext<BodyType>::task, &context);
}

// body(begin, end) over [0, count) in fixed chunks (the split depends on count only, never on the thread count).
template <class Body>
void parallel_for(std::size_t count, const ParallelSettings& settings, Body&& body) {
  parallel_for_chunks(count, settings,
                      [&body](std::size_t /*chunk*/, std::size_t begin, std::size_t end) { body(begin, end); });
}

}  // namespace hedra::collision
