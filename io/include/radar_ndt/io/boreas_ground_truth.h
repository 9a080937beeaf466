#pragma once
// Boreas ground truth: `<sequence>/applanix/<sensor>_poses.csv`, the post-processed pose of a
// sensor at each of its frames, read as the dataset's SDK reads it (pyboreas/utils/utils.py
// `get_transform`, pyboreas/utils/odometry.py `convert_line_to_pose`; docs/data_formats.md).
//
// Columns: GPSTime, easting, northing, altitude, vel_east, vel_north, vel_up, roll, pitch, heading,
// angvel_z, angvel_y, angvel_x. The pose is the sensor frame's in ENU: C_enu_sensor =
// roll(r) · pitch(p) · yaw(h) with the SDK's (passive) elementary rotations. For the radar the
// sensor frame is x forward, y right, z down (its roll is about ±π). GPSTime is in microseconds
// by the dataset's reference and in nanoseconds in the released files: both are read, by the
// number of digits as the SDK's time parser does.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "radar_ndt/io/trajectory_io.h"

namespace radar_ndt {

/// One row of a Boreas `*_poses.csv`.
struct BoreasPose {
  std::int64_t stamp_us = 0;                                   ///< GPSTime in µs (nanoseconds rounded down)
  double time_s = 0.0;                                         ///< GPSTime in seconds, as the SDK parses it
  Eigen::Vector3d position = Eigen::Vector3d::Zero();          ///< easting, northing, altitude (m)
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();          ///< ENU (m/s)
  double roll = 0, pitch = 0, heading = 0;                     ///< rad
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< about the sensor's x, y, z (rad/s)
  /// The column count of GPSTime's digits: 16 (µs) or 19 (ns) in the dataset.
  int time_digits = 0;
};

/// The SDK's C_enu_sensor (`yawPitchRollToRot(heading, pitch, roll)`). With `planar`, roll and
/// pitch are first rounded to multiples of π, as the SDK does for the 2D (radar) benchmark.
Eigen::Matrix3d boreasRotation(const BoreasPose& pose, bool planar);
/// The SDK's T_enu_sensor (`get_transform`; `planar` as above, the altitude then dropped).
Eigen::Isometry3d boreasSensorPose(const BoreasPose& pose, bool planar);

/// Reads a Boreas pose CSV. The header must name the 13 columns above (in that order); every row
/// has 13 finite numbers and a GPSTime at least a microsecond after the previous row's (times are
/// kept in µs). Throws IoError naming the file and line otherwise.
std::vector<BoreasPose> readBoreasPoses(const std::string& path);

/// Writes rows in the dataset's layout, atomically: GPSTime in nanoseconds (19 digits, as the
/// released files), 17 significant digits.
void writeBoreasPoses(const std::string& path, const std::vector<BoreasPose>& rows);

/// The radar's planar trajectory in the vehicle frame of this library (x forward, y left, z up;
/// seconds): T_enu_radar as the SDK's 2D benchmark builds it, times the fixed flip from the radar's
/// z-down axes. Relative motions are the SDK's radar-frame motions with y and yaw negated.
Trajectory boreasRadarTrajectory(const std::vector<BoreasPose>& rows);

/// The radar's full 6-DoF trajectory in the same axes (x forward, y left, z up; ENU, the altitude
/// kept; seconds): T_enu_radar with its roll and pitch, times the same flip. What drives the 4D
/// simulator with a car's real motion.
Trajectory boreasRadarTrajectory6Dof(const std::vector<BoreasPose>& rows);

/// A planar vehicle-frame pose (x forward, y left) as a Boreas radar pose row (roll π, pitch 0),
/// the inverse of boreasRadarTrajectory for one row.
BoreasPose boreasPoseFromPlanar(double time_s, double x, double y, double yaw, double vx, double vy, double yaw_rate);

}  // namespace radar_ndt
