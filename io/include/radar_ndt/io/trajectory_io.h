#pragma once
// Trajectory files: KITTI (12 numbers a line: the row-major 3x4 pose) and TUM
// (`t x y z qx qy qz qw`, quaternion Hamilton convention, scalar last). Lines starting with '#'
// and blank lines are skipped in both. Readers throw radar_ndt::IoError naming file and line.

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace radar_ndt {

/// A sequence of poses of the vehicle frame in a fixed world frame, with timestamps (s) when the
/// source had them (TUM) and none otherwise (KITTI).
struct Trajectory {
  std::vector<double> stamps;  ///< seconds; empty, or one per pose, strictly increasing
  std::vector<Eigen::Isometry3d> poses;

  std::size_t size() const { return poses.size(); }
  bool empty() const { return poses.empty(); }
  bool hasStamps() const { return !stamps.empty(); }

  /// The pose at time `t` (s): between the stamps around it, position along the straight line and
  /// rotation along the shorter arc (slerp; for planar poses the same as radar_ndt::interpolate);
  /// the pose itself at its own stamp. False without stamps, or when t lies outside them by more
  /// than 1 µs (then the nearest end's pose is used within that microsecond). The one lookup of a
  /// trajectory at a time: evaluation associates poses with it, the scanning run re-bases its
  /// ground truth with it.
  bool poseAt(double t, Eigen::Isometry3d* pose) const;
};

/// The pose a fraction `u` of the way from `a` to `b`: translation linear, rotation by slerp.
Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double u);

enum class TrajectoryFormat { Auto, Kitti, Tum };

/// "kitti", "tum" or "auto" (case-insensitive); throws std::invalid_argument otherwise.
TrajectoryFormat parseTrajectoryFormat(const std::string& name);

/// Reads a KITTI file. Each rotation block must be a rotation (orthonormal, det +1, to 1e-3);
/// NaN/Inf, a wrong count of numbers or an unparsable token is an error with its line number.
Trajectory readKitti(const std::string& path);

/// Reads a TUM file. Timestamps must be strictly increasing; quaternions are normalised (a norm
/// far from 1 or zero is an error).
Trajectory readTum(const std::string& path);

/// Auto: decides by the column count of the first data line (12: KITTI, 8: TUM).
Trajectory readTrajectory(const std::string& path, TrajectoryFormat format = TrajectoryFormat::Auto);

/// Writers replace `path` atomically (written to a temporary file beside it, then renamed), so an
/// interrupted run never leaves a half-written file under the final name. TUM needs stamps.
void writeKitti(const std::string& path, const Trajectory& trajectory);
void writeTum(const std::string& path, const Trajectory& trajectory);
void writeTrajectory(const std::string& path, const Trajectory& trajectory, TrajectoryFormat format);

}  // namespace radar_ndt
