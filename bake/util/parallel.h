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

// Limits every parallel loop of the process to `threads` worker threads while
// alive (0 = all cores). Create one at the start of a command.
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

}  // namespace texbake
