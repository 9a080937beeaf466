#pragma once
// Internal: the built-in 3D matchers, one file each (weighted_ndt_3d.cpp, pcl_ndt_3d.cpp,
// pcl_gicp.cpp). The 3D registry adds them, in this order, before its first use.

#include <vector>

#include "radar_ndt/odometry/matcher_registry_3d.h"

namespace radar_ndt {
namespace matchers {

Matcher3DEntry pwNdt3D();
Matcher3DEntry pclNdt3D();
Matcher3DEntry pclGicp();

inline std::vector<Matcher3DEntry> builtins3D() {
  return {pwNdt3D(), pclNdt3D(), pclGicp()};
}

}  // namespace matchers
}  // namespace radar_ndt
