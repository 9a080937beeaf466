#pragma once
// ROS times and the microseconds the readers and the run use, both ways, exact for times that are
// whole microseconds (a nuScenes timestamp written to a bag comes back unchanged).
#include <cstdint>

#include <ros/time.h>

namespace radar_ndt {
namespace ros1 {

inline std::int64_t microseconds(const ros::Time& t) {
  return static_cast<std::int64_t>(t.sec) * 1000000 + static_cast<std::int64_t>(t.nsec / 1000);
}

inline ros::Time rosTime(std::int64_t us) {
  ros::Time t;
  t.sec = static_cast<std::uint32_t>(us / 1000000);
  t.nsec = static_cast<std::uint32_t>((us % 1000000) * 1000);
  return t;
}

}  // namespace ros1
}  // namespace radar_ndt
