// A progress bar on stderr for long stages (SPEC section 5): drawn only when
// stderr is a terminal and --quiet is not given. advance() may be called from
// any thread (parallel_for_chunks calls it once per chunk); redraws happen
// only when the shown percentage changes, under a lock, so the cost per call
// is one atomic add.
#pragma once

#include <atomic>
#include <cstddef>
#include <mutex>
#include <string>

namespace texbake {

class Progress {
 public:
  // enabled = false: every call is a no-op (tests, --quiet, non-terminals).
  explicit Progress(bool enabled);
  ~Progress();  // ends an unfinished bar's line
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // For the CLI: enabled unless quiet, and only if stderr is a terminal.
  static bool stderr_is_terminal();

  // Starts a stage of `total` work items labelled `stage` ("bake", "fill"...).
  void start(const std::string& stage, std::size_t total);
  // `n` more items done. Thread-safe.
  void advance(std::size_t n);
  // Completes the current stage's line.
  void finish();

  bool enabled() const { return enabled_; }

 private:
  void draw(int percent);

  bool enabled_;
  std::mutex mutex_;
  std::string stage_;
  std::size_t total_ = 0;
  std::atomic<std::size_t> done_{0};
  std::atomic<int> shown_percent_{-1};
  bool active_ = false;
};

}  // namespace texbake
