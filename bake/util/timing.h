// Wall-clock timing of stages (the Stats timings of texbake/texbake.h).
#pragma once

#include <chrono>

namespace texbake {

using Clock = std::chrono::steady_clock;

// Seconds from `start` to now.
inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace texbake
