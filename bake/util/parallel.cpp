#include "bake/util/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <optional>

#include "mesh_io/tsan_fork_join.h"

namespace texbake {

struct ThreadLimitImpl {
  std::optional<tbb::global_control> control;
};

ThreadLimit::ThreadLimit(int threads) : impl_(std::make_unique<ThreadLimitImpl>()) {
  if (threads > 0) {
    impl_->control.emplace(tbb::global_control::max_allowed_parallelism,
                           static_cast<std::size_t>(threads));
  }
}

ThreadLimit::~ThreadLimit() = default;

void run_in_arena(int threads, const std::function<void()>& fn) {
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  ForkJoin fork_join;  // execute may run fn on another thread
  arena.execute([&] {
    fork_join.begin_body();
    fn();
    fork_join.end_body();
  });
  fork_join.join();
}

void parallel_for_chunks(std::size_t n, std::size_t grain,
                         const std::function<void(std::size_t, std::size_t)>& fn) {
  if (n == 0) return;
  grain = std::max<std::size_t>(grain, 1);
  // simple_partitioner with a fixed grain: chunk boundaries depend only on n
  // and grain, never on the thread count.
  ForkJoin fork_join;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, grain),
      [&](const tbb::blocked_range<std::size_t>& r) {
        fork_join.begin_body();
        fn(r.begin(), r.end());
        fork_join.end_body();
      },
      tbb::simple_partitioner());
  fork_join.join();
}

void parallel_for_blocks(std::size_t n, std::size_t size,
                         const std::function<void(std::size_t, std::size_t, std::size_t)>& fn) {
  size = std::max<std::size_t>(size, 1);
  parallel_for_chunks(block_count(n, size), 1, [&](std::size_t first, std::size_t last) {
    for (std::size_t b = first; b < last; ++b) fn(b, b * size, std::min(n, (b + 1) * size));
  });
}

struct BackgroundTaskImpl {
  tbb::task_group group;
  std::function<void()> fn;  // the task's work (held here: the task's closure is one pointer)
  ForkJoin fork_join;        // the task's hand-over, for ThreadSanitizer
  bool running = false;
};

BackgroundTask::BackgroundTask() : impl_(std::make_unique<BackgroundTaskImpl>()) {}

BackgroundTask::~BackgroundTask() {
  wait();
}

void BackgroundTask::run(std::function<void()> fn) {
  wait();
  BackgroundTaskImpl* impl = impl_.get();
  impl->fn = std::move(fn);
  impl->running = true;
  impl->fork_join.fork();
  // The closure holds only `impl`, copied into oneTBB's task by its own
  // header code (tests/tsan.supp's race_top entry): the task reads nothing
  // else of the caller's before begin_body().
  impl->group.run([impl] {
    impl->fork_join.begin_body();
    impl->fn();
    impl->fork_join.end_body();
  });
}

void BackgroundTask::wait() {
  if (!impl_->running) return;
  impl_->group.wait();
  impl_->fork_join.join();
  impl_->fn = nullptr;
  impl_->running = false;
}

}  // namespace texbake
