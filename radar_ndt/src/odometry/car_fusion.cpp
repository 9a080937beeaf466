#include "radar_ndt/odometry/car_fusion.h"

#include <cmath>

#include <Eigen/LU>

namespace radar_ndt {

void CarSensorOptions::validate() const {
  checkFields(*this, "CarSensorOptions");
}

CarFusion::CarFusion(const CarSensorOptions& car, const MotionFusionOptions& doppler) : car_(car), doppler_(doppler) {
  car_.validate();
  reset();
}

void CarFusion::reset() {
  x_.setZero();
  x_(4) = 1.0;
  P_.setZero();
  // The bias is the gyro's with a gyro, else the Doppler yaw-rate bias (as MotionFusion's).
  const double b = car_.gyro ? car_.gyro_bias_sigma : doppler_.options().yaw_rate_bias_sigma;
  P_(3, 3) = b * b;
  P_(4, 4) = car_.wheel_scale_sigma * car_.wheel_scale_sigma;
}

MotionEstimate CarFusion::predict(const CarMotion& car, const Pose2& doppler_motion, const Eigen::Matrix3d& fit,
                                  double dt, bool doppler_update) {
  dt = std::max(dt, 0.0);
  const double walk = car.has_yaw ? car_.gyro_bias_walk : doppler_.options().yaw_rate_bias_walk;
  P_(3, 3) += walk * walk * dt;
  P_(4, 4) += car_.wheel_scale_walk * car_.wheel_scale_walk * dt;
  const double b = x_(3), s = x_(4);
  const Eigen::Matrix3d doppler_cov = doppler_.dopplerCovariance(fit, dt);
  // The motion as a function of [b, s, n_d, n_θ, n_x, n_y]: the state's bias and scale and the
  // noises of the distance, the yaw and (without wheels) the Doppler translation.
  Eigen::Matrix<double, 6, 6> Q = Eigen::Matrix<double, 6, 6>::Zero();
  Q.topLeftCorner<2, 2>() = P_.bottomRightCorner<2, 2>();
  Q(2, 2) = car_.wheel_noise * car_.wheel_noise * dt * dt;
  Q(3, 3) = car.has_yaw ? car_.gyro_noise * car_.gyro_noise * dt : doppler_cov(2, 2);
  Q.bottomRightCorner<2, 2>() = doppler_cov.topLeftCorner<2, 2>();
  Eigen::Matrix<double, 5, 6> A = Eigen::Matrix<double, 5, 6>::Zero();
  const double theta = (car.has_yaw ? car.yaw : doppler_motion.z()) - b * dt;
  A(2, 0) = -dt;
  A(2, 3) = 1;
  A(3, 0) = 1;
  A(4, 1) = 1;
  Vector5d x;
  x << doppler_motion.x(), doppler_motion.y(), theta, b, s;
  if (car.has_distance) {
    // Along the arc the rear axle rolled: its chord, of length d·sinc(θ/2), at θ/2.
    const double d = s * car.distance, half = 0.5 * theta;
    const double sinc = std::abs(half) < 1e-9 ? 1.0 : std::sin(half) / half;
    const Eigen::Vector2d along(std::cos(half) * sinc, std::sin(half) * sinc);
    const Eigen::Vector2d turn = 0.5 * d * sinc * Eigen::Vector2d(-std::sin(half), std::cos(half));
    x.head<2>() = d * along;
    A.block<2, 1>(0, 0) = -dt * turn;
    A.block<2, 1>(0, 1) = car.distance * along;
    A.block<2, 1>(0, 2) = along;
    A.block<2, 1>(0, 3) = turn;
  } else {
    A(0, 4) = 1;
    A(1, 5) = 1;
  }
  x_ = x;
  P_ = A * Q * A.transpose();
  if (car.has_distance && doppler_update)
    correct(Eigen::MatrixXd::Identity(2, 5), doppler_motion.head<2>(), doppler_cov.topLeftCorner<2, 2>(), false);
  return estimate();
}

MotionEstimate CarFusion::update(const Pose2& match, const Eigen::Matrix3d& match_covariance) {
  correct(Eigen::MatrixXd::Identity(3, 5), match, match_covariance, true);
  return estimate();
}

void CarFusion::correct(const Eigen::MatrixXd& H, const Eigen::VectorXd& z, const Eigen::MatrixXd& R, bool yaw_in_z) {
  const Eigen::MatrixXd S = H * P_ * H.transpose() + R;
  const Eigen::MatrixXd K = P_ * H.transpose() * S.inverse();
  Eigen::VectorXd innovation = z - H * x_;
  if (yaw_in_z) innovation(2) = std::remainder(innovation(2), 2.0 * kPi);
  x_ += K * innovation;
  x_(2) = std::remainder(x_(2), 2.0 * kPi);
  const Matrix5d P = (Matrix5d::Identity() - K * H) * P_;
  P_ = 0.5 * (P + P.transpose());
}

MotionEstimate CarFusion::estimate() const {
  return {x_.head<3>(), P_.topLeftCorner<3, 3>()};
}

}  // namespace radar_ndt
