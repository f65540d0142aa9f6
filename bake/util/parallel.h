// Parallel loops for texbake's hot paths. This is the only header that knows
// about the thread library (oneTBB); everything else calls parallel_for_chunks.
//
// Determinism rule: fn must write only to its own items' outputs and derive
// any randomness from the item index, so results never depend on the thread
// count or scheduling (SPEC section 5, --threads).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

namespace texbake {

// Runs fn() inside a task arena of `threads` threads (0 = all cores): every
// parallel loop fn starts runs on at most that many threads (the calling
// thread among them), without limiting what other threads of the process
// run (texbake/texbake.h's RunOptions::threads). Exceptions from fn
// propagate.
void run_in_arena(int threads, const std::function<void()>& fn);

// Limits every parallel loop of the process to `threads` worker threads while
// alive (0 = all cores). Process-wide: the library uses run_in_arena; this
// remains for the tests and benchmarks that compare thread counts.
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  std::unique_ptr<struct ThreadLimitImpl> impl_;
};

// Calls fn(begin, end) on disjoint chunks covering [0, n), of about `grain`
// items each, in parallel. fn is called once per chunk: hoist per-chunk
// set-up (scratch buffers, std::visit dispatch) out of the item loop.
void parallel_for_chunks(std::size_t n, std::size_t grain,
                         const std::function<void(std::size_t begin, std::size_t end)>& fn);

// Calls fn(block, begin, end) for the fixed blocks [block * size, min(n,
// (block + 1) * size)) of [0, n), in parallel: block boundaries depend on n
// and size alone (parallel_for_chunks' chunks are not aligned to its grain),
// so per-block partial results summed in block order never depend on the
// thread count.
void parallel_for_blocks(
    std::size_t n, std::size_t size,
    const std::function<void(std::size_t block, std::size_t begin, std::size_t end)>& fn);

// One task run beside the caller's own work, on the threads of the caller's
// task arena (so RunOptions::threads bounds it too: with one thread it runs
// when waited for). Work whose result the caller takes later, such as
// decoding the next photo while this one is baked. The destructor waits.
class BackgroundTask {
 public:
  BackgroundTask();
  ~BackgroundTask();
  BackgroundTask(const BackgroundTask&) = delete;
  BackgroundTask& operator=(const BackgroundTask&) = delete;
  // Starts fn; precondition: no task of this object is running (wait()).
  void run(std::function<void()> fn);
  // Returns once the task started by run() has finished (at once if none).
  void wait();

 private:
  std::unique_ptr<struct BackgroundTaskImpl> impl_;
};

// The number of blocks parallel_for_blocks(n, size, ...) calls fn for.
inline std::size_t block_count(std::size_t n, std::size_t size) {
  return (n + size - 1) / size;
}

}  // namespace texbake
