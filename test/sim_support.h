#pragma once
// Helpers shared by the simulator's tests: a straight drive, the radiate profile's sensor with and
// without its random artefacts, and where a return's edge and mean power lie along an azimuth.
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/sim/radar_sim.h"

namespace radar_ndt {
namespace test {

/// Straight drive along +x at `speed` m/s for 10 s.
inline sim::SimTrajectory straight(double speed) {
  std::vector<double> t;
  std::vector<Pose2> p;
  for (int k = 0; k <= 40; ++k) {
    t.push_back(0.25 * k);
    p.emplace_back(speed * 0.25 * k, 0.0, 0.0);
  }
  return sim::SimTrajectory(t, p);
}

/// The radiate profile's sensor (the plain log display these geometric checks were written for),
/// with no random artefacts (ghosts, saturation lines, ground clutter). The geometry (ray casting,
/// per-azimuth timing) is the same code for every profile.
inline sim::ScanningOptions radiate() {
  sim::WorldOptions w;
  sim::ScanningOptions o;
  sim::applyProfile(sim::ScanningProfile::Radiate, w, o);
  return o;
}
inline sim::ScanningOptions clean() {
  sim::ScanningOptions o = radiate();
  o.ghost_probability = 0.0;
  o.saturation_probability = 0.0;
  o.ground_clutter_cover = 0.0;
  return o;
}

/// Range (m) of the leading edge of the strongest return along azimuth `a` between `lo` and `hi`
/// metres: the first bin above half way from the noise floor to the peak (a surface returns from
/// its front face over its depth, so the edge, not the peak, is where it is).
inline double edgeRange(const PolarScan& s, int a, double lo, double hi) {
  int best = -1, first = -1;
  double floor = 0;
  int n = 0;
  for (int b = 0; b < s.bins; ++b) {
    const double r = s.rangeOf(b);
    if (r < lo || r > hi) continue;
    if (first < 0) first = b;
    floor += s.row(a)[b];
    ++n;
    if (best < 0 || s.row(a)[b] > s.row(a)[best]) best = b;
  }
  floor /= n;
  const double half = 0.5 * (floor + s.row(a)[best]);
  int b = best;
  while (b > first && s.row(a)[b - 1] > half) --b;
  return s.rangeOf(b);
}

/// Mean pixel value along azimuth `a` within [lo, hi] m.
inline double meanPower(const PolarScan& s, int a, double lo, double hi) {
  double sum = 0;
  int n = 0;
  for (int b = 0; b < s.bins; ++b) {
    const double r = s.rangeOf(b);
    if (r < lo || r > hi) continue;
    sum += s.row(a)[b];
    ++n;
  }
  return sum / n / 255.0;
}

}  // namespace test
}  // namespace radar_ndt
