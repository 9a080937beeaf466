#include "radar_ndt/odometry/motion_fusion.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace radar_ndt {

void MotionFusionOptions::validate() const {
  checkFields(*this, "MotionFusionOptions");
}

MotionFusion::MotionFusion(const MotionFusionOptions& options) : options_(options) {
  options_.validate();
  reset();
}

void MotionFusion::reset() {
  bias_ = 0;
  bias_var_ = options_.yaw_rate_bias_sigma * options_.yaw_rate_bias_sigma;
  predicted_.setZero();
  joint_.setZero();
}

Eigen::Matrix3d MotionFusion::dopplerCovariance(const Eigen::Matrix3d& fit, double dt) const {
  const Eigen::Vector3d s(options_.doppler_sigma_x, options_.doppler_sigma_y, options_.doppler_sigma_yaw);
  return fit + (s.cwiseProduct(s) * (dt * dt)).asDiagonal().toDenseMatrix();
}

Eigen::Matrix3d MotionFusion::matchCovariance(const Eigen::Matrix3d* reported, MatchCalibration calibration) const {
  const MotionFusionOptions& o = options_;
  if (reported && reported->allFinite()) {
    const Eigen::LLT<Eigen::Matrix3d> llt(*reported);
    const double scale = calibration == MatchCalibration::Rapp ? o.rapp_covariance_scale : o.match_covariance_scale;
    if (llt.info() == Eigen::Success) return scale * *reported;
  }
  const Eigen::Vector3d s = calibration == MatchCalibration::PclIcp
                                ? Eigen::Vector3d(o.icp_sigma_x, o.icp_sigma_y, o.icp_sigma_yaw)
                                : Eigen::Vector3d(o.match_sigma_x, o.match_sigma_y, o.match_sigma_yaw);
  return s.cwiseProduct(s).asDiagonal();
}

MotionEstimate MotionFusion::predict(const Pose2& doppler_motion, const Eigen::Matrix3d& fit, double dt) {
  // The bias walks over dt; the motion's yaw is θ_d − b·dt, so Cov(yaw, b) = −dt·Var(b).
  bias_var_ += options_.yaw_rate_bias_walk * options_.yaw_rate_bias_walk * std::max(dt, 0.0);
  predicted_ = doppler_motion;
  predicted_.z() -= bias_ * dt;
  joint_.setZero();
  joint_.topLeftCorner<3, 3>() = dopplerCovariance(fit, dt);
  joint_(2, 2) += bias_var_ * dt * dt;
  joint_(2, 3) = joint_(3, 2) = -bias_var_ * dt;
  joint_(3, 3) = bias_var_;
  return {predicted_, joint_.topLeftCorner<3, 3>()};
}

MotionEstimate MotionFusion::update(const Pose2& match, const Eigen::Matrix3d& match_covariance) {
  // The match observes the motion part of the state directly (H = [I 0]).
  const Eigen::Matrix3d S = joint_.topLeftCorner<3, 3>() + match_covariance;
  const Eigen::Matrix<double, 4, 3> K = joint_.leftCols<3>() * S.inverse();
  Pose2 innovation = match - predicted_;
  innovation.z() = std::remainder(innovation.z(), 2.0 * kPi);
  const Eigen::Vector4d dx = K * innovation;
  Eigen::Matrix4d I_KH = Eigen::Matrix4d::Identity();
  I_KH.leftCols<3>() -= K;
  const Eigen::Matrix4d joint = I_KH * joint_;
  bias_ += dx(3);
  bias_var_ = joint(3, 3);
  MotionEstimate fused;
  fused.motion = predicted_ + dx.head<3>();
  fused.motion.z() = std::remainder(fused.motion.z(), 2.0 * kPi);
  fused.covariance = 0.5 * (joint.topLeftCorner<3, 3>() + joint.topLeftCorner<3, 3>().transpose());
  return fused;
}

}  // namespace radar_ndt
