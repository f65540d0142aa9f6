#include "bake/util/progress.h"

#include <unistd.h>

#include <cstdio>

namespace texbake {

namespace {
constexpr int kBarWidth = 40;
}

Progress::Progress(bool enabled) : enabled_(enabled) {}

Progress::~Progress() {
  finish();
}

bool Progress::stderr_is_terminal() {
  return ::isatty(STDERR_FILENO) == 1;
}

void Progress::start(const std::string& stage, std::size_t total) {
  if (!enabled_) return;
  finish();
  std::lock_guard<std::mutex> lock(mutex_);
  stage_ = stage;
  total_ = total;
  done_.store(0);
  shown_percent_.store(-1);
  active_ = true;
  draw(0);
}

void Progress::advance(std::size_t n) {
  if (!enabled_) return;
  const std::size_t done = done_.fetch_add(n) + n;
  const int percent = total_ == 0 ? 100 : static_cast<int>(done * 100 / total_);
  int shown = shown_percent_.load();
  // Only the thread that moves the shown percentage forward redraws.
  while (percent > shown) {
    if (shown_percent_.compare_exchange_weak(shown, percent)) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (active_ && percent >= shown_percent_.load()) draw(percent);
      return;
    }
  }
}

void Progress::finish() {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!active_) return;
  draw(100);
  std::fputc('\n', stderr);
  std::fflush(stderr);
  active_ = false;
}

void Progress::draw(int percent) {
  if (percent > 100) percent = 100;
  const int filled = percent * kBarWidth / 100;
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kBarWidth - filled), '-');
  std::fprintf(stderr, "\r%-8s [%s] %3d%%", stage_.c_str(), bar.c_str(), percent);
  std::fflush(stderr);
}

}  // namespace texbake
