#pragma once
// One 6-axis IMU message, what a 4D radar rig's IMU gives: read from a bag
// (ros/rosbag_sequence.h), simulated (sim/motion_6dof.h), fused (odometry/doppler_imu.h).

#include <Eigen/Core>

namespace radar_ndt {

/// One IMU message in the body frame: the gyro (rad/s) and the accelerometer's specific force
/// (m/s²: at rest it reads +g along the body's up).
struct ImuSample {
  double t = 0;  ///< s
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();
};

}  // namespace radar_ndt
