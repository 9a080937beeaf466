#pragma once
// The registry of matchers, as small_gicp registers its odometry engines: a name maps to a factory
// and to what the matcher can use of a radar's points. --method, makeMatcher, both benchmarks and
// Python read it. A new matcher is one file with its factory and one registration line: built-in
// ones in radar_ndt/src/odometry/matchers/ (listed in builtin_matchers.h), a user's through
// registerMatcher() before the run that names it.

#include <functional>
#include <string>
#include <vector>

#include "radar_ndt/odometry/matcher.h"
#include "radar_ndt/odometry/motion_fusion.h"

namespace radar_ndt {

/// What a matcher uses of the points beyond their positions, and so what the pipelines hand it.
struct MatcherUses {
  bool power_weights = false;    ///< weighs points by power: the power shift (and its halving) applies
  bool doppler_weights = false;  ///< weighs points by Doppler agreement (Rapp): the moving detections stay in
  bool needs_doppler = false;    ///< needs Doppler: automotive radars only
  bool sweep_times = false;      ///< places each point at its time in the sweep (--compensation joint)
  bool merges_source = false;    ///< merges its source into voxels itself; others get merged scanning points
  bool three_d = false;          ///< matches in 3D (none yet; the pipelines are planar)
  // What a method needs of the car's own sensors (the car-sensor baselines; CarFusion):
  bool gyro = false;           ///< the car's gyro (odometry.car.gyro on)
  bool wheels = false;         ///< the car's wheel speeds (odometry.car.wheels on)
  bool doppler_fusion = true;  ///< false: the Doppler motion is not fused (the car's own dead reckoning)
  /// Whether only the automotive pipeline can run it (Doppler, or the car's CAN bus: no scanning
  /// sequence has either yet).
  bool automotiveOnly() const { return needs_doppler || gyro || wheels; }
};

struct MatcherEntry {
  std::string name;  ///< as --method and Python's method= spell it
  std::string help;  ///< a phrase: what the method is
  MatcherUses uses;
  /// How the automotive fusion trusts its matches (MotionFusionOptions).
  MatchCalibration calibration = MatchCalibration::WeightedNdt;
  /// A new matcher at options.nominal(); an empty adapter: the method matches nothing (the
  /// odometry dead-reckons on its prior).
  std::function<MatcherAdapter(const MatcherOptions&)> make;
};

/// Adds `entry`; std::invalid_argument for an empty name or factory, or a name already taken.
void registerMatcher(MatcherEntry entry);
/// The entry named `name`; std::invalid_argument naming the registered ones otherwise.
const MatcherEntry& findMatcher(const std::string& name);
/// The registered names, built-in ones first, in the order they were registered.
std::vector<std::string> matcherNames();

}  // namespace radar_ndt
