// The bridge from the library's stages to a progress callback (the
// RunOptions::progress of texbake/texbake.h): a stage is started with its
// number of work items, the parallel loops advance it once per chunk, and
// the callback hears (stage, fraction) at most about every percent, never
// concurrently with itself, with fractions that never decrease within a
// stage: 0 when the stage starts, 1 when it finishes.
//
// The callback returning false cancels: every later call to the callback is
// skipped, cancelled() turns true, and the loops that check it per chunk
// (bake_vertex, bake_atlas, render_preview) skip their remaining chunks and
// return cancelled_error() instead of a result.
//
// Cost: an empty callback makes every call a no-op; otherwise advance() is
// one atomic add, plus a lock only when the shown percentage moves forward.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>

#include "mapping/error.h"

namespace texbake {

class Progress {
 public:
  // callback(stage, fraction) -> keep going; may be empty (nothing is
  // reported, nothing cancels).
  explicit Progress(std::function<bool(std::string_view stage, double fraction)> callback = {});
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Starts the stage `stage` of `total` work items and reports (stage, 0).
  // Not thread-safe: call between parallel loops.
  void start(std::string_view stage, std::size_t total);
  // `n` more items of the current stage done. Thread-safe; reports
  // done / total when its whole percentage grew.
  void advance(std::size_t n);
  // Reports (stage, 1) unless already reported. Not thread-safe.
  void finish();

  // A callback returned false. Thread-safe; cheap enough to ask per chunk.
  bool cancelled() const { return cancelled_.load(std::memory_order_relaxed); }

 private:
  void report(int percent);  // under mutex_

  std::function<bool(std::string_view, double)> callback_;
  std::mutex mutex_;
  std::string stage_;
  std::size_t total_ = 0;
  std::atomic<std::size_t> done_{0};
  std::atomic<int> shown_percent_{-1};
  int reported_percent_ = -1;  // under mutex_
  std::atomic<bool> cancelled_{false};
};

// The error of a call stopped by its progress callback (kCancelled).
inline Error cancelled_error() {
  return make_error(ErrorCode::kCancelled, "cancelled by the progress callback");
}

// True when `progress` is set and cancelled (for loops given a nullable Progress*).
inline bool is_cancelled(const Progress* progress) {
  return progress && progress->cancelled();
}

}  // namespace texbake
