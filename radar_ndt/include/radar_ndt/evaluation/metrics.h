#pragma once
// Odometry metrics. Each is defined exactly here and in docs/metrics.md.
//
// All take a PosePairs: ground truth and estimate associated pose by pose, by index (when either
// trajectory has no timestamps, e.g. KITTI files; then the lengths must match) or by timestamp
// (both TUM: ground truth interpolated at each estimate's stamp, linear in position and slerp in
// rotation; estimates outside the ground truth's time span are dropped).

#include <cstddef>
#include <limits>
#include <vector>

#include <Eigen/Geometry>

#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

struct PosePairs {
  std::vector<Eigen::Isometry3d> gt;
  std::vector<Eigen::Isometry3d> est;
  std::vector<double> stamps;  ///< the estimate's stamps when associated by time, else empty
  std::size_t size() const { return gt.size(); }
};

/// Throws std::invalid_argument when the trajectories cannot be associated (index association with
/// different lengths, no overlap in time, fewer than 2 pairs).
PosePairs associate(const Trajectory& gt, const Trajectory& est);

/// An error with nothing to average (no segment, no pair) is undefined: NaN, printed "n/a" and
/// written as JSON null, never 0 (which would read as a perfect estimate).
constexpr double kUndefinedError = std::numeric_limits<double>::quiet_NaN();

/// Segment-based relative error (KITTI and 1m metrics). Errors are NaN when `segments` is 0, e.g.
/// the KITTI metric on a trajectory shorter than 100 m.
struct SegmentError {
  struct PerLength {
    double length = 0;  ///< nominal segment length (m)
    double trans_err_pct = kUndefinedError;
    double rot_err_deg_per_m = kUndefinedError;
    std::size_t segments = 0;
  };
  double trans_err_pct = kUndefinedError;      ///< mean over all segments of ‖t(E)‖ / L, in %
  double rot_err_deg_per_m = kUndefinedError;  ///< mean over all segments of angle(R(E)) / L, in deg/m
  std::size_t segments = 0;
  std::vector<PerLength> per_length;
};

/// KITTI devkit definition: first frame every `step`-th pose; for each L in `lengths` the last frame
/// is the first whose ground-truth path length from the first frame exceeds L;
/// E = (est_first⁻¹ est_last)⁻¹ (gt_first⁻¹ gt_last); errors ‖t(E)‖/L and acos((tr R(E) − 1)/2)/L,
/// averaged over all segments of all lengths. Segments that run past the end are not counted.
SegmentError kittiError(const PosePairs& pairs,
                        const std::vector<double>& lengths = {100, 200, 300, 400, 500, 600, 700, 800},
                        std::size_t step = 10);

/// The paper's nuScenes "1 m" metric: every pose is a first frame; the segment ends at the first pose
/// whose ground-truth path length from it reaches `length`; errors are divided by that segment's
/// actual path length (not the nominal one).
SegmentError oneMeterError(const PosePairs& pairs, double length = 1.0);

struct FrameError {
  double trans_err_m = kUndefinedError;  ///< mean ‖t(E)‖ over pairs (m/frame); NaN without pairs
  double rot_err_deg = kUndefinedError;  ///< mean angle(R(E)) over pairs (deg/frame); NaN without pairs
  std::size_t pairs = 0;
};

/// Mean relative pose error over consecutive pose pairs (i, i+step), i = 0, step, 2 step, …
/// (step > 1 subsamples, e.g. 13 Hz automotive cycles to about 4 Hz with step 3).
FrameError frameError(const PosePairs& pairs, std::size_t step = 1);

struct AbsoluteError {
  double rmse_m = 0;  ///< RMSE of x-y positions after alignment
  std::size_t poses = 0;
  Pose2 alignment = Pose2::Zero();  ///< the SE(2) transform applied to the estimate
};

/// ATE: RMSE of the x-y positions after the least-squares SE(2) alignment (rotation about z and
/// translation, no scale; closed form) of the estimate to the ground truth.
AbsoluteError absoluteTrajectoryError(const PosePairs& pairs);

/// Path length along the ground truth (3D distances between consecutive positions), cumulative.
std::vector<double> pathDistances(const std::vector<Eigen::Isometry3d>& poses);

/// Rotation angle of a rotation matrix (rad), acos((trace − 1)/2) with the argument clamped.
double rotationAngle(const Eigen::Matrix3d& R);

}  // namespace radar_ndt
