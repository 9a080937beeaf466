#pragma once
// Per-detection position covariance for automotive radars, in the vehicle frame.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <pcl/point_cloud.h>

#include "radar_ndt/frontend/ego_velocity.h"
#include "radar_ndt/point_types.h"

namespace radar_ndt {

enum class PointCovarianceModel {
  Polar,        ///< range and azimuth σ from the sensor spec, through the polar→Cartesian Jacobian
  ReportedRms,  ///< the sensor's own x_rms/y_rms (sensor frame), where the file has them
};

/// "polar" or "rms"; throws std::invalid_argument otherwise.
PointCovarianceModel parsePointCovarianceModel(const std::string& name);
const char* toString(PointCovarianceModel model);

/// Continental ARS408-21 data sheet accuracies, read as 1σ: range ±0.10 m (near range, up to
/// 70 m) and ±0.40 m (far range); azimuth ±0.1° straight ahead growing to ±1° at ±60° and beyond.
struct PolarAccuracy {
  double range_sigma_near = 0.10;
  double range_sigma_far = 0.40;
  double near_range = 70.0;
  double azimuth_sigma_center_deg = 0.1;
  double azimuth_sigma_edge_deg = 1.0;
  double edge_azimuth_deg = 60.0;
};

/// Covariance of a detection at (x, y) in the sensor frame under the polar model (sensor frame).
Eigen::Matrix2d polarCovariance(double x, double y, const PolarAccuracy& accuracy);

/// Sets cov_xx, cov_xy, cov_yy of every point of `cloud_sensor` (sensor frame, as read) to its
/// covariance rotated into the vehicle frame by the mounting yaw. ReportedRms uses the cov fields
/// the reader filled (x_rms², y_rms²) and falls back to the polar model where they are 0.
void setPointCovariances(pcl::PointCloud<PointRadar>& cloud_sensor, double mounting_yaw, PointCovarianceModel model,
                         const PolarAccuracy& accuracy);

}  // namespace radar_ndt
