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

}  // namespace radar_ndt
