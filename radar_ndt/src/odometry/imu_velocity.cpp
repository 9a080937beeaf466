#include "radar_ndt/odometry/imu_velocity.h"

#include <algorithm>

#include "radar_ndt/se3.h"

namespace radar_ndt {

Eigen::Vector3d predictBodyVelocity(const Eigen::Matrix3d& attitude, const Eigen::Vector3d& velocity,
                                    const ImuSample& from, std::vector<ImuSample>::const_iterator first,
                                    std::vector<ImuSample>::const_iterator last, double until,
                                    const Eigen::Vector3d& gyro_bias, const Eigen::Vector3d& accel_bias,
                                    double gravity) {
  Eigen::Matrix3d R = attitude;
  Eigen::Vector3d v = velocity;
  ImuSample a = from;
  auto step = [&](const ImuSample& b) {
    const double dt = b.t - a.t;
    if (!(dt > 0)) return;
    const Eigen::Vector3d omega = 0.5 * (a.gyro + b.gyro) - gyro_bias;
    const Eigen::Vector3d f = 0.5 * (a.accel + b.accel) - accel_bias;
    const Eigen::Matrix3d R_mid = R * expSO3(0.5 * dt * omega);
    const Eigen::Vector3d acceleration = f - R_mid.transpose() * Eigen::Vector3d(0, 0, gravity);
    v += (acceleration - omega.cross(v)) * dt;
    R = R * expSO3(omega * dt);
    a = b;
  };
  for (; first != last; ++first) {
    if (first->t <= from.t) continue;
    if (first->t > until) break;
    step(*first);
  }
  if (a.t < until) {
    ImuSample held = a;  // the last reading held to `until`
    held.t = until;
    step(held);
  }
  return v;
}

Eigen::Matrix3d predictedVelocityCovariance(const Eigen::Matrix3d& accepted_covariance, double seconds, double floor,
                                            double accel_sigma) {
  const double s = accel_sigma * std::max(0.0, seconds);
  return accepted_covariance + (floor * floor + s * s) * Eigen::Matrix3d::Identity();
}

}  // namespace radar_ndt
