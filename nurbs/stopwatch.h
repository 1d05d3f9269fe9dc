#pragma once
/// \file stopwatch.h
/// Seconds of wall time since a steady-clock instant: the figures every query reports.
#include <chrono>

namespace nurbs {

using Clock = std::chrono::steady_clock;

[[nodiscard]] inline double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace nurbs
