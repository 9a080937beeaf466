#pragma once
// Per-detection position covariance for automotive radars, in the vehicle frame.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <pcl/point_cloud.h>

#include "radar_ndt/fields.h"
#include "radar_ndt/frontend/ego_velocity.h"
#include "radar_ndt/point_types.h"

namespace radar_ndt {

enum class PointCovarianceModel {
  Polar,        ///< range and azimuth σ from the sensor spec, through the polar→Cartesian Jacobian
  ReportedRms,  ///< the sensor's own x_rms/y_rms (sensor frame), where the file has them
};

template <>
struct EnumNames<PointCovarianceModel> {
  static constexpr const char* what = "point covariance model";
  static constexpr EnumName<PointCovarianceModel> names[] = {
      {PointCovarianceModel::Polar, "polar", "ARS408 range/azimuth spec"},
      {PointCovarianceModel::ReportedRms, "rms", "the reported x_rms/y_rms"}};
};

/// Continental ARS408-21 data sheet accuracies, read as 1σ: range ±0.10 m (near range, up to
/// 70 m) and ±0.40 m (far range); azimuth ±0.1° straight ahead growing to ±1° at ±60° and beyond.
struct PolarAccuracy {
  double range_sigma_near = 0.10;
  double range_sigma_far = 0.40;
  double near_range = 70.0;
  double azimuth_sigma_center_deg = 0.1;
  double azimuth_sigma_edge_deg = 1.0;
  double edge_azimuth_deg = 60.0;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void PolarAccuracy::fields(Visit&& visit) {
  using S = PolarAccuracy;
  visit(&S::range_sigma_near, Field("range_sigma_near", "range 1σ in the near range").unit("m").positive());
  visit(&S::range_sigma_far, Field("range_sigma_far", "range 1σ beyond it").unit("m").positive());
  visit(&S::near_range, Field("near_range", "where the near range ends").unit("m").atLeast(0));
  visit(&S::azimuth_sigma_center_deg,
        Field("azimuth_sigma_center_deg", "azimuth 1σ straight ahead").unit("deg").positive());
  visit(&S::azimuth_sigma_edge_deg, Field("azimuth_sigma_edge_deg", "azimuth 1σ at the edge").unit("deg").positive());
  visit(&S::edge_azimuth_deg, Field("edge_azimuth_deg", "where the edge begins").unit("deg").atLeast(0));
}

/// Covariance of a detection at (x, y) in the sensor frame under the polar model (sensor frame).
Eigen::Matrix2d polarCovariance(double x, double y, const PolarAccuracy& accuracy);

/// Sets cov_xx, cov_xy, cov_yy of every point of `cloud_sensor` (sensor frame, as read) to its
/// covariance rotated into the vehicle frame by the mounting yaw. ReportedRms uses the cov fields
/// the reader filled (x_rms², y_rms²) and falls back to the polar model where they are 0.
void setPointCovariances(pcl::PointCloud<PointRadar>& cloud_sensor, double mounting_yaw, PointCovarianceModel model,
                         const PolarAccuracy& accuracy);

/// A 4D radar's accuracy as 1σ in its own spherical coordinates (the sensor description's): range
/// (m), azimuth and elevation (deg). A 4D radar's elevation is far coarser than its azimuth.
struct SphericalAccuracy {
  double range_sigma = 0.1;
  double azimuth_sigma_deg = 1.0;
  double elevation_sigma_deg = 3.0;
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void SphericalAccuracy::fields(Visit&& visit) {
  using S = SphericalAccuracy;
  visit(&S::range_sigma, Field("range_sigma", "range 1σ").unit("m").positive());
  visit(&S::azimuth_sigma_deg, Field("azimuth_sigma_deg", "azimuth 1σ").unit("deg").positive());
  visit(&S::elevation_sigma_deg, Field("elevation_sigma_deg", "elevation 1σ").unit("deg").positive());
}

/// Covariance of a detection at (x, y, z) in the sensor frame (x forward, y left, z up; azimuth
/// about z from x, elevation from the x-y plane): Σ = J diag(σr², σaz², σel²) Jᵀ with J the
/// Jacobian of the position in (range, azimuth, elevation). Zero at the origin.
Eigen::Matrix3d sphericalCovariance(const Eigen::Vector3d& p, const SphericalAccuracy& accuracy);

/// Sets the covariance of every point of `cloud` (sensor frame, as read) to sphericalCovariance
/// rotated into the vehicle frame by the mounting's rotation R (R Σ Rᵀ).
void setPointCovariances(pcl::PointCloud<PointRadar4D>& cloud, const Eigen::Matrix3d& mounting_rotation,
                         const SphericalAccuracy& accuracy);

}  // namespace radar_ndt
