#pragma once
// Boreas's IMU file, `<sequence>/applanix/imu.csv`, as the dataset documents it (pyboreas
// DATA_REFERENCE.md, "Pose Files": "t, wz, wy, wx, az, ay, ax" in the Applanix frame, x right,
// y forward, z up; the released files name the columns GPSTime, angvel_z, angvel_y, angvel_x,
// accelz, accely, accelx). Angular rates in rad/s, accelerations in m/s²; the time column as in
// the pose files (digits decide: s, µs or ns). The scanning pipeline reads the yaw rate (z up:
// counter-clockwise positive, as the library's vehicle frame).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "radar_ndt/io/vehicle_signals.h"

namespace radar_ndt {

/// One row of applanix/imu.csv, in the Applanix frame (x right, y forward, z up).
struct BoreasImuRow {
  std::int64_t stamp_us = 0;
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< rad/s (x, y, z)
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();      ///< m/s² (x, y, z)
};

/// The rows of `path` in file order. Throws IoError naming the file (and line) for a missing
/// column, a value that is not a finite number, a time that is not one, or times that do not
/// increase.
std::vector<BoreasImuRow> readBoreasImuFile(const std::string& path);

/// `<sequence_dir>/applanix/imu.csv` as the car's signals (its yaw rate; no wheel speeds); nullopt
/// when the file does not exist. Errors as readBoreasImuFile.
std::optional<VehicleSignals> readBoreasImu(const std::string& sequence_dir);

/// Writes `rows` as the released files lay them out (header GPSTime,angvel_z,angvel_y,angvel_x,
/// accelz,accely,accelx; times in ns), atomically.
void writeBoreasImu(const std::string& path, const std::vector<BoreasImuRow>& rows);

}  // namespace radar_ndt
