#pragma once
// Automotive radar cycles: one sweep of every radar, clocked by a reference radar, and the
// front-end that turns a cycle into one cloud in the vehicle frame at the reference time: point
// covariances, Doppler ego-velocity, moving detections removed, sweeps compensated to the
// reference time.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>

#include "radar_ndt/frontend/doppler_outlier_removal.h"
#include "radar_ndt/frontend/ego_velocity.h"
#include "radar_ndt/frontend/point_covariance.h"
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

/// A cycle after the front-end: one cloud in the vehicle frame at the reference time, planar
/// (z = 0: the sensors' mounting height is not an elevation measurement).
struct ProcessedCycle {
  std::int64_t timestamp_us = 0;
  pcl::PointCloud<PointRadar>::Ptr cloud{new pcl::PointCloud<PointRadar>};
  EgoVelocity ego;
  std::vector<SensorMounting> mountings;  ///< by sensor_id, for Doppler predictions downstream
  std::size_t raw_points = 0;             ///< detections read (after the reader's filters)
  std::size_t removed_moving = 0;         ///< removed by the Doppler outlier filter
};

struct AutomotiveFrontEndOptions {
  PointCovarianceModel covariance_model = PointCovarianceModel::Polar;
  PolarAccuracy polar;
  EgoVelocityOptions ego_velocity;
  /// Remove detections that disagree with the ego-velocity (Kellner's RANSAC outliers).
  bool remove_moving = true;
  /// Move each sweep to the reference time with the ego-velocity (constant over the cycle).
  bool compensate_time = true;
  /// Throws std::invalid_argument naming the setting out of range.
  void validate() const;
};

class AutomotiveFrontEnd {
 public:
  AutomotiveFrontEnd() = default;
  /// Validates `o` (std::invalid_argument).
  explicit AutomotiveFrontEnd(const AutomotiveFrontEndOptions& o) : options_(o) { options_.validate(); }
  const AutomotiveFrontEndOptions& options() const { return options_; }

  /// When the ego-velocity of this cycle cannot be estimated (too few stationary detections),
  /// `fallback` (e.g. the previous cycle's) is used for the filter and the time compensation, and
  /// the result's ego.valid stays false.
  ProcessedCycle process(const RadarCycle& cycle, const EgoVelocity* fallback = nullptr) const;

 private:
  AutomotiveFrontEndOptions options_;
};

}  // namespace radar_ndt
