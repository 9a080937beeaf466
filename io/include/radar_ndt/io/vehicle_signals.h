#pragma once
// A car's own motion sensors over a recording, as time series (what a CAN bus reader returns and
// the automotive odometry fuses; io/nuscenes_can_bus.h reads nuScenes').

#include <cstddef>
#include <string>

#include "radar_ndt/time_series.h"

namespace radar_ndt {

/// A car's own motion sensors over a recording.
struct VehicleSignals {
  TimeSeries yaw_rate;        ///< rad/s about z up (counter-clockwise positive)
  TimeSeries rear_wheel_rpm;  ///< the rear wheels' mean speed, rpm (× 2π r / 60: m/s)
  /// The vehicle's forward speed, m/s, where a recording gives it instead of the wheels' rpm (a ROS
  /// speed topic); the rpm are used when there are both.
  TimeSeries speed;
  std::size_t dropped = 0;  ///< messages left out for a missing (NaN) value
  std::string source;       ///< where they were read from, for messages
};

}  // namespace radar_ndt
