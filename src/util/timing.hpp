#pragma once
// ddt::seconds_since — wall-clock seconds elapsed since a steady_clock
// time point: the stage timings every pipeline and the command line print.

#include <chrono>

namespace ddt {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace ddt
