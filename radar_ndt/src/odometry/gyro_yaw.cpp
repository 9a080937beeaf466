#include "radar_ndt/odometry/gyro_yaw.h"

#include <cmath>

#include "radar_ndt/se2.h"

namespace radar_ndt {

void GyroOptions::validate() const {
  checkFields(*this, "GyroOptions");
}

GyroYaw::GyroYaw(const GyroOptions& options) : options_(options) {
  options_.validate();
  reset();
}

void GyroYaw::reset() {
  x_.setZero();
  P_.setZero();
  P_(1, 1) = options_.bias_sigma * options_.bias_sigma;
}

double GyroYaw::predict(double gyro_yaw, double dt) {
  dt = std::max(dt, 0.0);
  // The bias walks over dt; the yaw is the gyro's minus the bias over dt, with the gyro's noise.
  const double p_b = P_(1, 1) + options_.bias_walk * options_.bias_walk * dt;
  x_ << gyro_yaw - x_(1) * dt, x_(1);
  P_ << dt * dt * p_b + options_.noise * options_.noise * dt, -dt * p_b, -dt * p_b, p_b;
  return x_(0);
}

double GyroYaw::update(double match_yaw, bool* fused) {
  const double r = options_.match_yaw_sigma * options_.match_yaw_sigma;
  const double s = P_(0, 0) + r;
  const double innovation = std::remainder(match_yaw - x_(0), 2.0 * kPi);
  const bool ok = innovation * innovation <= options_.gate * options_.gate * s;
  if (fused) *fused = ok;
  if (!ok) return x_(0);
  const Eigen::Vector2d k = P_.col(0) / s;
  x_ += k * innovation;
  const Eigen::Matrix2d P = P_ - k * P_.row(0);
  P_ = 0.5 * (P + P.transpose());
  return x_(0);
}

}  // namespace radar_ndt
