#pragma once
// The doppler-imu baseline: what a 4D radar and an IMU know without any scan matching, as
// EKF-RIO (Doer and Trommer 2020) and Kubelka et al. ("Do we need scan-matching in radar
// odometry?", 2024) run it. The orientation is the gyro integrated, its roll and pitch pulled
// towards gravity (a complementary filter) by the accelerometer less the body's own acceleration
// as the Doppler velocity and the gyro give it (dv/dt + ω × v), whenever what is left reads about
// 1 g; the position is the Doppler body velocity (ego_velocity_3d.h, bodyVelocity) turned into the
// world by that orientation and integrated. Yaw is unobserved and drifts with the gyro's bias; the
// bias is taken from the first still half second. Every 6-DoF accuracy table holds this row, as
// the planar ones hold `wheel-gyro`.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/imu_sample.h"
#include "radar_ndt/io/trajectory_io.h"

namespace radar_ndt {

/// The body's velocity (m/s, body axes) at time t, as bodyVelocity() gives it from one scan.
struct BodyVelocitySample {
  double t = 0;  ///< s, the scan's time as recorded (DopplerImuOptions::radar_latency is taken off)
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  bool valid = true;  ///< false: the scan had no estimate; its pose is still written (velocity held)
  /// m²/s², the estimate's (ego_velocity_3d.h); zero: velocity_gate_floor alone says its error
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

struct DopplerImuOptions {
  double gravity = 9.81;                ///< m/s²
  double attitude_time_constant = 2.0;  ///< s: how fast roll and pitch follow gravity while still
  double still_tolerance = 0.5;         ///< m/s²: | |f| − g | below it, the accelerometer is gravity
  double initial_seconds = 0.5;         ///< s of IMU at the start: roll, pitch, the gyro's bias
  double radar_latency = 0.0;           ///< s: the scans' recorded times minus their measurement's
  double max_imu_gap = 0.1;             ///< s: longer gaps between IMU messages are reported
  /// Each velocity gated by the IMU's prediction from the last accepted one (imu_velocity.h), as
  /// EKF-RIO gates its radar velocity and as the fused odometry's velocity_prior does; one beyond
  /// the gate is held over as an invalid one is.
  bool velocity_gate = true;
  double velocity_gate_floor = 0.1;  ///< m/s: the prediction's smallest 1σ
  double velocity_gate_sigma = 0.3;  ///< m/s²: how fast the prediction's 1σ grows
  /// Throws std::invalid_argument naming the setting out of range.
  void validate() const;
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void DopplerImuOptions::fields(Visit&& visit) {
  using S = DopplerImuOptions;
  visit(&S::gravity, Field("gravity", "the local gravity").unit("m/s^2").positive());
  visit(&S::attitude_time_constant,
        Field("attitude_time_constant", "how fast roll and pitch follow gravity while still").unit("s").positive());
  visit(&S::still_tolerance,
        Field("still_tolerance", "| |accelerometer| - g | below which it reads gravity").unit("m/s^2").positive());
  visit(&S::initial_seconds,
        Field("initial_seconds", "IMU at the start that gives roll, pitch and the gyro's bias").unit("s").positive());
  visit(&S::radar_latency,
        Field("radar_latency", "the scans' recorded times minus their measurement's").unit("s").atLeast(0));
  visit(&S::max_imu_gap, Field("max_imu_gap", "longer gaps between IMU messages are reported").unit("s").positive());
  visit(&S::velocity_gate,
        Field("velocity_gate", "each scan's Doppler velocity gated by the IMU's prediction from the last accepted"));
  visit(&S::velocity_gate_floor,
        Field("velocity_gate_floor", "the IMU's predicted velocity's smallest 1 sigma").unit("m/s").atLeast(0));
  visit(&S::velocity_gate_sigma,
        Field("velocity_gate_sigma", "how fast the IMU's predicted velocity grows uncertain").unit("m/s^2").positive());
}

struct DopplerImuResult {
  /// A pose per velocity sample inside the IMU's time span (body to world: the world's z up, its
  /// x the body's heading at the start, its origin where the body was at the IMU's first
  /// message), stamped with the sample's time minus the latency.
  Trajectory trajectory;
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();  ///< rad/s, taken off every gyro reading
  std::size_t held_velocities = 0;                      ///< invalid samples whose neighbours' velocity was used
  std::size_t gated_velocities = 0;                     ///< valid samples the gate refused (held over too)
  /// Each problem met, said once with its figures: IMU messages out of order or not finite, gaps,
  /// gravity along another axis than the body's z, a start that was not still.
  std::vector<std::string> problems;
};

/// Runs the baseline over a recording's IMU messages and scans' body velocities (either in any
/// order: both are sorted by time). With velocity_gate, a first pass gives the attitude the
/// prediction turns gravity with, and the run is made again without the refused velocities. Throws
/// std::invalid_argument when there is no usable IMU message or no valid velocity.
DopplerImuResult runDopplerImu(std::vector<ImuSample> imu, std::vector<BodyVelocitySample> velocities,
                               const DopplerImuOptions& options = {});

}  // namespace radar_ndt
