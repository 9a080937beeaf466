#pragma once
// Automotive radar cycles as a dataset gives them: one sweep of every radar, clocked by a
// reference radar (the cycle's time is the reference sweep's), each sweep's points in its sensor
// frame with the sensor's mounting beside them. Planning which sweeps form a cycle is dataset
// access; turning a cycle into one cloud is the front-end's (frontend/automotive_front_end.h).

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>

#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// A sweep's time and channel, for planning cycles.
struct SweepStamp {
  std::int64_t timestamp_us = 0;
  std::uint16_t channel = 0;
};

/// One cycle: `reference` and, per other channel that has one, its latest sweep within one period
/// before the reference sweep (t_ref − period < t ≤ t_ref). Indices into the planned list.
struct CyclePlan {
  std::size_t reference = 0;
  std::vector<std::size_t> members;  ///< includes `reference`, in channel order
};

/// Plans the cycles of a time-ordered sweep list. `period_us` ≤ 0: the median interval of the
/// reference channel's sweeps.
std::vector<CyclePlan> planRadarCycles(const std::vector<SweepStamp>& sweeps, std::uint16_t reference_channel,
                                       std::int64_t period_us = 0);

/// Where a radar sits on the vehicle (vehicle frame: x forward, y left), in 2D.
struct SensorMounting {
  double x = 0, y = 0, yaw = 0;
  bool valid = false;  ///< false for sensor ids no sweep of this cycle came from
};

/// The 2D mounting (x, y, yaw) of a sensor-to-vehicle calibration.
SensorMounting toMounting(const Eigen::Isometry3d& sensor_to_vehicle);

/// One radar's sweep as read: points in the sensor frame.
struct RadarSweepData {
  std::int64_t timestamp_us = 0;
  std::uint16_t sensor_id = 0;
  Eigen::Isometry3d sensor_to_vehicle = Eigen::Isometry3d::Identity();
  pcl::PointCloud<PointRadar> points;
};

struct RadarCycle {
  std::int64_t timestamp_us = 0;  ///< the reference sweep's time: the cycle's pose time
  std::vector<RadarSweepData> sweeps;
};

}  // namespace radar_ndt
