#include "bake/util/progress.h"

#include <algorithm>
#include <utility>

namespace texbake {

Progress::Progress(std::function<bool(std::string_view, double)> callback)
    : callback_(std::move(callback)) {}

void Progress::start(std::string_view stage, std::size_t total) {
  if (!callback_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  stage_ = stage;
  total_ = total;
  done_.store(0);
  shown_percent_.store(0);
  reported_percent_ = -1;
  report(0);
}

void Progress::advance(std::size_t n) {
  if (!callback_ || cancelled()) return;
  const std::size_t done = done_.fetch_add(n) + n;
  const int percent =
      total_ == 0 ? 100 : static_cast<int>(std::min<std::size_t>(done, total_) * 100 / total_);
  int shown = shown_percent_.load();
  // Only the thread that moves the shown percentage forward reports.
  while (percent > shown) {
    if (shown_percent_.compare_exchange_weak(shown, percent)) {
      std::lock_guard<std::mutex> lock(mutex_);
      // Another thread may have reported a later percentage meanwhile.
      if (percent > reported_percent_) report(percent);
      return;
    }
  }
}

void Progress::finish() {
  if (!callback_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  shown_percent_.store(100);
  if (reported_percent_ < 100) report(100);
}

void Progress::report(int percent) {
  reported_percent_ = percent;
  if (cancelled()) return;
  if (!callback_(stage_, percent / 100.0)) cancelled_.store(true);
}

}  // namespace texbake
