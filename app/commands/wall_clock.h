// The wall-clock time of a command's phases, as its report and run.json give it: a steady clock, in seconds.
#pragma once
#include <chrono>

namespace wobble {

using Clock = std::chrono::steady_clock;

inline double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace wobble
