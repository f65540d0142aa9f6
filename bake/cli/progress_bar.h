// The progress bar of SPEC section 5 on stderr: drawn only when stderr is a
// terminal and --quiet is not given. It is the RunOptions::progress callback
// of texbake/texbake.h (the library calls it never concurrently, at most
// about every percent), one line per stage:
//   bake     [################------------------------]  40%
#pragma once

#include <string>
#include <string_view>

#include "texbake/texbake.h"

namespace texbake::cli {

class ProgressBar {
 public:
  // enabled = false: callback() is empty and nothing is drawn.
  explicit ProgressBar(bool enabled);
  ~ProgressBar();  // ends an unfinished stage's line
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // For the CLI: enabled unless quiet, and only if stderr is a terminal.
  static bool stderr_is_terminal();

  // The callback drawing this bar (never cancels); empty when disabled. The
  // bar must outlive the calls that use it.
  ProgressCallback callback();

 private:
  void draw(std::string_view stage, double fraction);
  void end_line();

  bool enabled_;
  bool active_ = false;  // a stage's line is open
  std::string stage_;
};

}  // namespace texbake::cli
