#include "radar_ndt/frontend/point_covariance.h"
#include "radar_ndt/se2.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace radar_ndt {

Eigen::Matrix2d polarCovariance(double x, double y, const PolarAccuracy& a) {
  const double r = std::hypot(x, y);
  const double az = std::atan2(y, x);
  const double sr = r <= a.near_range ? a.range_sigma_near : a.range_sigma_far;
  const double edge = a.edge_azimuth_deg * kPi / 180.0;
  const double frac = edge > 0 ? std::min(std::abs(az) / edge, 1.0) : 1.0;
  const double sa =
      (a.azimuth_sigma_center_deg + frac * (a.azimuth_sigma_edge_deg - a.azimuth_sigma_center_deg)) * kPi / 180.0;
  // J = ∂(x, y)/∂(r, θ) = [[cos θ, −r sin θ], [sin θ, r cos θ]]; Σ = J diag(σr², σθ²) Jᵀ.
  Eigen::Matrix2d J;
  J << std::cos(az), -r * std::sin(az), std::sin(az), r * std::cos(az);
  return J * Eigen::Vector2d(sr * sr, sa * sa).asDiagonal() * J.transpose();
}

void setPointCovariances(pcl::PointCloud<PointRadar>& cloud, double yaw, PointCovarianceModel model,
                         const PolarAccuracy& accuracy) {
  Eigen::Matrix2d R;
  R << std::cos(yaw), -std::sin(yaw), std::sin(yaw), std::cos(yaw);
  for (auto& p : cloud) {
    Eigen::Matrix2d S;
    if (model == PointCovarianceModel::ReportedRms && p.cov_xx > 0.f && p.cov_yy > 0.f)
      S << p.cov_xx, p.cov_xy, p.cov_xy, p.cov_yy;
    else
      S = polarCovariance(p.x, p.y, accuracy);
    const Eigen::Matrix2d C = R * S * R.transpose();
    p.cov_xx = static_cast<float>(C(0, 0));
    p.cov_xy = static_cast<float>(C(0, 1));
    p.cov_yy = static_cast<float>(C(1, 1));
  }
}

Eigen::Matrix3d sphericalCovariance(const Eigen::Vector3d& p, const SphericalAccuracy& a) {
  const double rho = std::hypot(p.x(), p.y());
  const double r = p.norm();
  if (!(r > 0)) return Eigen::Matrix3d::Zero();
  const double az = std::atan2(p.y(), p.x()), el = std::atan2(p.z(), rho);
  const double ca = std::cos(az), sa = std::sin(az), ce = std::cos(el), se = std::sin(el);
  // p = r (cos el cos az, cos el sin az, sin el); columns ∂p/∂r, ∂p/∂az, ∂p/∂el.
  Eigen::Matrix3d J;
  J << ce * ca, -r * ce * sa, -r * se * ca,  //
      ce * sa, r * ce * ca, -r * se * sa,    //
      se, 0.0, r * ce;
  const double deg = kPi / 180.0;
  const Eigen::Vector3d var(a.range_sigma * a.range_sigma, std::pow(a.azimuth_sigma_deg * deg, 2),
                            std::pow(a.elevation_sigma_deg * deg, 2));
  return J * var.asDiagonal() * J.transpose();
}

void setPointCovariances(pcl::PointCloud<PointRadar4D>& cloud, const Eigen::Matrix3d& R, const SphericalAccuracy& a) {
  for (auto& p : cloud) {
    const Eigen::Matrix3d C = R * sphericalCovariance(Eigen::Vector3d(p.x, p.y, p.z), a) * R.transpose();
    p.cov_xx = static_cast<float>(C(0, 0));
    p.cov_xy = static_cast<float>(C(0, 1));
    p.cov_xz = static_cast<float>(C(0, 2));
    p.cov_yy = static_cast<float>(C(1, 1));
    p.cov_yz = static_cast<float>(C(1, 2));
    p.cov_zz = static_cast<float>(C(2, 2));
  }
}

}  // namespace radar_ndt
