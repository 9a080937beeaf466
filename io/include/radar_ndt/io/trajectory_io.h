#pragma once
// Trajectory files: KITTI (12 numbers a line: the row-major 3x4 pose), TUM
// (`t x y z qx qy qz qw`, quaternion Hamilton convention, scalar last) and the Boreas odometry
// leaderboard's (below). Lines starting with '#' and blank lines are skipped in all. Readers throw radar_ndt::IoError
// naming file and line.

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "radar_ndt/fields.h"

namespace radar_ndt {

/// A sequence of poses of the vehicle frame in a fixed world frame, with timestamps (s) when the
/// source had them (TUM) and none otherwise (KITTI).
struct Trajectory {
  std::vector<double> stamps;  ///< seconds; empty, or one per pose, strictly increasing
  std::vector<Eigen::Isometry3d> poses;
  /// Set by the readers: how many rotation blocks of the file were not orthonormal (rounded
  /// numbers) and were projected onto rotations, and the largest max|RᵀR − I| among them.
  std::size_t projected_rotations = 0;
  double max_rotation_deviation = 0.0;

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

/// Boreas: the Boreas odometry leaderboard's file (pyboreas/eval/odometry.md): a line per scan,
/// `<timestamp µs>` and the row-major 3x4 of T_rk_r0, the transform from the first radar frame to
/// scan k's, in the radar's axes (x forward, y right, z down); read back as vehicle poses. Rotation
/// blocks are re-orthogonalised as the Boreas SDK does on reading (pyboreas utils.enforce_orthog),
/// so that the file scores as the SDK scores it; counted as for KITTI.
enum class TrajectoryFormat { Auto, Kitti, Tum, Boreas };
template <>
struct EnumNames<TrajectoryFormat> {
  static constexpr const char* what = "trajectory format";
  static constexpr EnumName<TrajectoryFormat> names[] = {
      {TrajectoryFormat::Auto, "auto", "by the file"},
      {TrajectoryFormat::Kitti, "kitti", "KITTI"},
      {TrajectoryFormat::Tum, "tum", "TUM"},
      {TrajectoryFormat::Boreas, "boreas", "the Boreas odometry leaderboard's"}};
};

/// A TrajectoryFormat's name in any case ("KITTI", "tum"); throws std::invalid_argument otherwise.
TrajectoryFormat parseTrajectoryFormat(const std::string& name);

/// Reads a KITTI file. A rotation block that is not orthonormal (a file rounded to few decimals) is
/// replaced by the nearest rotation and counted in projected_rotations; one that no rounding
/// explains (max|RᵀR − I| > 0.05 or det <= 0), NaN/Inf, a wrong count of numbers or an unparsable
/// token is an error with its line number.
Trajectory readKitti(const std::string& path);

/// Reads a TUM file. Timestamps must be strictly increasing; quaternions are normalised (a norm
/// far from 1 or zero is an error).
Trajectory readTum(const std::string& path);

/// Auto: a Boreas pose CSV (`GPSTime,...` header, boreas_ground_truth.h) is read as the radar's
/// vehicle-frame trajectory; otherwise by the column count of the first data line (12: KITTI,
/// 8: TUM, 13: Boreas odometry).
Trajectory readTrajectory(const std::string& path, TrajectoryFormat format = TrajectoryFormat::Auto);

/// The format readTrajectory's Auto finds in the file (a Boreas pose CSV counts as Boreas); throws
/// as it does when there is none.
TrajectoryFormat detectTrajectoryFormat(const std::string& path);

/// Writers replace `path` atomically (written to a temporary file beside it, then renamed), so an
/// interrupted run never leaves a half-written file under the final name. TUM needs stamps.
void writeKitti(const std::string& path, const Trajectory& trajectory);
void writeTum(const std::string& path, const Trajectory& trajectory);
/// Needs stamps, as TUM.
void writeBoreasOdometry(const std::string& path, const Trajectory& trajectory);
void writeTrajectory(const std::string& path, const Trajectory& trajectory, TrajectoryFormat format);

}  // namespace radar_ndt
