#pragma once
// Internal: the built-in matchers, one file each (weighted_ndt.cpp, pcl_ndt.cpp, pcl_icp.cpp,
// doppler.cpp, car.cpp). The registry adds them, in this order, before its first use.

#include "radar_ndt/odometry/matcher_registry.h"

namespace radar_ndt {
namespace matchers {

MatcherEntry pwNdt();
MatcherEntry pclNdt();
MatcherEntry pclIcp();
MatcherEntry doppler();
MatcherEntry rappNdt();
MatcherEntry wheelGyro();
MatcherEntry dopplerGyro();

/// Every built-in matcher, one line each.
inline std::vector<MatcherEntry> builtins() {
  return {pwNdt(), pclNdt(), pclIcp(), doppler(), rappNdt(), wheelGyro(), dopplerGyro()};
}

}  // namespace matchers
}  // namespace radar_ndt
