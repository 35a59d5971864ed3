// The default TaskRunner: a persistent pool of hardware_concurrency() - 1
// std::threads, the calling thread being the last worker.
//
// One job at a time: run() takes the pool with try_lock; when another thread
// holds it (two embedder threads calling at once), or when the caller is a
// pool worker (a nested parallel_for), the job runs inline on the caller,
// which gives the same results (chunks, not workers, decide the outputs).
//
// A job: the caller publishes (task, context, count) under the mutex and
// bumps the generation; every worker that sees a new generation registers
// itself as active, takes indices from the atomic counter until they run
// out, and deregisters. The caller takes indices too, then waits until no
// worker is active. Invariant: a worker holds the job's fields only while
// it is active, and a new job is published only when none is active, so no
// worker ever runs an index of one job with the task of another.
#include <condition_variable>
#include <cstdint>
#include <hedra/collision/parallel.hpp>
#include <hedra/hull/assert.hpp>
#include <mutex>
#include <thread>
#include <vector>

namespace hedra::collision {
namespace {

thread_local bool t_inside_pool = false;

void run_inline(std::size_t count, void (*task)(std::size_t, void*), void* context) {
  for (std::size_t i = 0; i < count; ++i) task(i, context);
}

class ThreadPool final : public TaskRunner {
 public:
  explicit ThreadPool(int threads) {
    for (int i = 1; i < threads; ++i) workers_.emplace_back([this] { work(); });
  }
  ~ThreadPool() override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
  }
  int concurrency() const override { return static_cast<int>(workers_.size()) + 1; }

  void run(std::size_t count, void (*task)(std::size_t, void*), void* context) override {
    if (count <= 1 || workers_.empty() || t_inside_pool) return run_inline(count, task, context);
    std::unique_lock<std::mutex> job(job_mutex_, std::try_to_lock);
    if (!job.owns_lock()) return run_inline(count, task, context);
    {
      std::unique_lock<std::mutex> lock(mutex_);
      idle_.wait(lock, [this] { return active_ == 0; });
      task_ = task;
      context_ = context;
      count_ = count;
      next_.store(0, std::memory_order_relaxed);
      ++generation_;
    }
    wake_.notify_all();
    t_inside_pool = true;
    take_indices(task, context, count);
    t_inside_pool = false;
    std::unique_lock<std::mutex> lock(mutex_);
    idle_.wait(lock, [this] { return active_ == 0; });
    // Every index was taken (the caller's loop ended) and every worker that
    // took one has finished it (none is active).
    HEDRA_ASSERT(next_.load() >= count);
  }

 private:
  void take_indices(void (*task)(std::size_t, void*), void* context, std::size_t count) {
    for (std::size_t i = next_.fetch_add(1, std::memory_order_acq_rel); i < count;
         i = next_.fetch_add(1, std::memory_order_acq_rel))
      task(i, context);
  }

  void work() {
    t_inside_pool = true;
    std::uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      ++active_;
      void (*task)(std::size_t, void*) = task_;
      void* context = context_;
      const std::size_t count = count_;
      lock.unlock();
      take_indices(task, context, count);
      lock.lock();
      if (--active_ == 0) idle_.notify_all();
    }
  }

  std::vector<std::thread> workers_;
  std::mutex job_mutex_;  // held by the caller of the running job
  std::mutex mutex_;      // guards the fields below but next_
  std::condition_variable wake_, idle_;
  std::uint64_t generation_ = 0;
  int active_ = 0;
  bool stop_ = false;
  void (*task_)(std::size_t, void*) = nullptr;
  void* context_ = nullptr;
  std::size_t count_ = 0;
  std::atomic<std::size_t> next_{0};
};

}  // namespace

TaskRunner& default_task_runner() {
  static ThreadPool pool(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  return pool;
}

int parallel_workers(const ParallelSettings& settings) {
  if (settings.threads == 1) return 1;
  const TaskRunner& runner = settings.runner ? *settings.runner : default_task_runner();
  const int available = std::max(1, runner.concurrency());
  return settings.threads <= 0 ? available : std::min(settings.threads, available);
}

}  // namespace hedra::collision
