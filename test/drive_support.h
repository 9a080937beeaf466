#pragma once
// A simulated drive shared by the 6-DoF tests (the odometry's and the run's).
#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "radar_ndt/io/trajectory_io.h"

namespace radar_ndt {
namespace test {

inline  /// A drive at 4 Hz: still 3 s, then up to about 8 m/s along a long left curve over a gentle hill.
    Trajectory
    curveDrive(double seconds) {
  Trajectory t;
  double s_along = 0, yaw = 0;
  Eigen::Vector2d xy(0, 0);
  for (double s = 0; s <= seconds; s += 0.25) {
    const double speed = s < 3 ? 0 : 8 * std::min(1.0, (s - 3) / 5);
    s_along += speed * 0.25;
    yaw += speed * 0.25 / 80.0 * (s > 10 ? 1 : 0);
    xy += speed * 0.25 * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const double pitch = -0.03 * std::cos(s_along / 30.0);
    T.translation() = Eigen::Vector3d(xy.x(), xy.y(), 0.9 * std::sin(s_along / 30.0));
    T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
                     .toRotationMatrix();
    t.stamps.push_back(50 + s);
    t.poses.push_back(T);
  }
  return t;
}

}  // namespace test
}  // namespace radar_ndt
