#pragma once
// radar_sim --realism: real scans of an Oxford, Boreas or RADIATE sequence against simulated ones
// in the same layout, per range band and through the front-end (sim/scan_statistics.h), as tables;
// optionally a PNG of a real and a simulated scan side by side.

#include <cstdint>
#include <string>
#include <vector>

#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/sim/radar_sim.h"

namespace radar_ndt {
namespace apps {

/// The real scans of an Oxford (radar.timestamps, radar/<stamp>.png), Boreas (radar/<stamp>.png, no
/// index) or RADIATE (Navtech_Polar/) sequence directory, and the layout's name.
std::vector<PolarScan> readRealScans(const std::string& dir, std::string& layout);

struct RealismRequest {
  std::string dir;              ///< the real sequence
  std::string layout;           ///< its layout's name (readRealScans)
  std::vector<PolarScan> real;  ///< its scans
  std::size_t frames = 10;      ///< simulated scans, spread over the trajectory from `start`
  std::size_t start = 0;
  std::uint64_t seed = 1;
  double threshold = 0.333;  ///< the front-end's threshold of the comparison
  std::string png;           ///< a real and a simulated scan side by side (empty: none)
  double view_range = 62.5;  ///< the PNG shows ±this many metres
  sim::ScanningProfile profile = sim::ScanningProfile::Oxford;
  std::string source;  ///< the trajectory's name, for the heading
};

/// Prints the comparison (and writes the PNG); `scanning` is the profile's sensor, its geometry
/// replaced by the real scans'.
void runRealism(const RealismRequest& request, const sim::SimTrajectory& ego, const sim::WorldOptions& world,
                sim::ScanningOptions scanning);

}  // namespace apps
}  // namespace radar_ndt
