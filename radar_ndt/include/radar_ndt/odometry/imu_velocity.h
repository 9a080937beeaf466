#pragma once
// The body velocity an IMU predicts from the last scan's: dv/dt = a − ω × v in the body's axes,
// a = f − b_a − Rᵀ g ẑ the body's acceleration from the accelerometer's specific force f (the
// inertial filter's gravity model, inertial_filter.h). Its use: a gate on the next scan's Doppler
// velocity (ego_velocity_3d.h, EgoVelocityPrior), as EKF-RIO (Doer and Trommer 2020) gates the
// radar's velocity by the Mahalanobis distance from its IMU-propagated state, and the velocity
// that moves the prior when the scan gives none.

#include <vector>

#include <Eigen/Core>

#include "radar_ndt/io/imu_sample.h"

namespace radar_ndt {

/// Carries `velocity` (body axes, m/s) and `attitude` (body to world, the world's z up) from
/// `from.t` over the messages [first, last) (time-ordered) up to `until`, the last reading held to
/// it; messages at or before from.t are passed over. Biases are taken off the readings.
Eigen::Vector3d predictBodyVelocity(const Eigen::Matrix3d& attitude, const Eigen::Vector3d& velocity,
                                    const ImuSample& from, std::vector<ImuSample>::const_iterator first,
                                    std::vector<ImuSample>::const_iterator last, double until,
                                    const Eigen::Vector3d& gyro_bias, const Eigen::Vector3d& accel_bias,
                                    double gravity);

/// The prediction's covariance: the last accepted velocity's, plus on every axis `floor` (m/s,
/// 1σ of what is wrong at any time: the Doppler fit's own error beyond its covariance, the two
/// clocks' offset under a jerk) and `accel_sigma` (m/s², 1σ of what the accelerometer's
/// integration gets wrong: attitude, bias) times the time since it, in quadrature. Linear in that
/// time, not its square root: those errors are steady over seconds, not white, and a gate that
/// grew more slowly than the prediction drifts would lock the true velocity out.
Eigen::Matrix3d predictedVelocityCovariance(const Eigen::Matrix3d& accepted_covariance, double seconds, double floor,
                                            double accel_sigma);

}  // namespace radar_ndt
