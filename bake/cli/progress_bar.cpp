#include "bake/cli/progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace texbake::cli {

namespace {
constexpr int kBarWidth = 40;
}

ProgressBar::ProgressBar(bool enabled) : enabled_(enabled) {}

ProgressBar::~ProgressBar() {
  end_line();
}

bool ProgressBar::stderr_is_terminal() {
  return ::isatty(STDERR_FILENO) == 1;
}

ProgressCallback ProgressBar::callback() {
  if (!enabled_) return {};
  return [this](std::string_view stage, double fraction) {
    draw(stage, fraction);
    return true;
  };
}

void ProgressBar::draw(std::string_view stage, double fraction) {
  if (active_ && stage != stage_) end_line();
  stage_ = stage;
  active_ = true;
  const int percent = std::clamp(static_cast<int>(std::lround(fraction * 100)), 0, 100);
  const int filled = percent * kBarWidth / 100;
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kBarWidth - filled), '-');
  std::fprintf(stderr, "\r%-9s [%s] %3d%%", stage_.c_str(), bar.c_str(), percent);
  std::fflush(stderr);
  if (percent == 100) end_line();
}

void ProgressBar::end_line() {
  if (!active_) return;
  std::fputc('\n', stderr);
  std::fflush(stderr);
  active_ = false;
}

}  // namespace texbake::cli
