#pragma once
// Internal: the wall-clock helpers the run drivers (automotive_run.cpp, scanning_run.cpp) and
// Odometry share for their per-stage timings.
#include <algorithm>
#include <chrono>
#include <vector>

#include "radar_ndt/statistics.h"

namespace radar_ndt {
namespace detail {

using Clock = std::chrono::steady_clock;

inline double msBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}
inline double msSince(Clock::time_point t0) {
  return msBetween(t0, Clock::now());
}

/// The upper median (0 for no values).
using radar_ndt::median;  // radar_ndt/statistics.h: 0 for no samples

}  // namespace detail
}  // namespace radar_ndt
