#pragma once
// Internal to the simulator: small helpers its renderers and writers share.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "radar_ndt/se2.h"
#include "radar_ndt/sim/radar_sim.h"
#include "sim_random.h"

namespace radar_ndt {
namespace sim {
namespace detail {

constexpr double kDeg = kPi / 180.0;

inline double dbToLinear(double db) {
  return std::pow(10.0, 0.1 * db);
}

inline std::int64_t toMicros(double seconds) {
  return static_cast<std::int64_t>(std::llround(seconds * 1e6));
}

/// A nuScenes-style 32-hex-digit token, fixed by the seed, a kind and an index.
inline std::string token(std::uint64_t seed, std::uint64_t kind, std::uint64_t index) {
  std::uint64_t x = seed * 0x9e3779b97f4a7c15ULL ^ (kind << 48) ^ index;
  const std::uint64_t a = splitmix64(x), b = splitmix64(x);
  char buf[33];
  std::snprintf(buf, sizeof buf, "%016llx%016llx", static_cast<unsigned long long>(a),
                static_cast<unsigned long long>(b));
  return buf;
}

inline void progressLine(bool on, const char* what, std::size_t k, std::size_t n) {
  if (!on) return;
  if (k + 1 == n || k % 10 == 0) std::fprintf(stderr, "\r%s %zu/%zu", what, k + 1, n);
  if (k + 1 == n) std::fprintf(stderr, "\n");
}

/// What a writer reports: `frames` over `duration` s of `ego` from t0, and the wall time since
/// `wall`.
inline SequenceSummary summarize(const SimTrajectory& ego, double t0, std::size_t frames, double duration,
                                 std::chrono::steady_clock::time_point wall) {
  SequenceSummary summary;
  summary.frames = frames;
  summary.duration = duration;
  summary.distance = ego.arcAt(t0 + duration) - ego.arcAt(t0);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
  return summary;
}

}  // namespace detail
}  // namespace sim
}  // namespace radar_ndt
