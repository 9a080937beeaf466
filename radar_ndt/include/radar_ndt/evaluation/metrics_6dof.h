#pragma once
// 6-DoF odometry metrics, as rpg_trajectory_evaluation (Zhang & Scaramuzza 2018; its
// src/rpg_trajectory_evaluation/*.py) defines them for visual- and radar-inertial odometry, and
// the final position error of closed loops. Each is defined exactly here and in docs/metrics.md;
// test_metrics_6dof checks them against values that project's own code computed on fixtures.
// A trajectory is 6-DoF when any pose leaves the plane (isPlanar); planar ones keep the metrics of
// metrics.h.

#include <cstddef>
#include <vector>

#include <Eigen/Geometry>

#include "radar_ndt/evaluation/metrics.h"

namespace radar_ndt {

/// True when every pose lies in the plane z = 0 and turns about z only (within `tolerance`, m and
/// rotation-matrix entries): what the planar pipelines write.
bool isPlanar(const std::vector<Eigen::Isometry3d>& poses, double tolerance = 1e-6);
bool isPlanar(const PosePairs& pairs, double tolerance = 1e-6);

/// How the estimate is aligned to the ground truth before the absolute error: the least-squares
/// rotation and translation of all positions (Umeyama without scale: rpg's `se3`), or the
/// least-squares yaw and translation (rpg's `posyaw`: roll and pitch are observable through
/// gravity in an inertial odometry, so they are not aligned away).
enum class TrajectoryAlignment { SE3, PositionYaw };

/// gt ≈ T · est over all associated positions (rpg align_umeyama, known scale; yaw_only for
/// PositionYaw).
Eigen::Isometry3d alignTrajectory(const PosePairs& pairs, TrajectoryAlignment alignment);

struct AbsoluteError6Dof {
  double rmse_m = kUndefinedError;        ///< RMSE of the 3D positions after the alignment
  double rot_rmse_deg = kUndefinedError;  ///< RMSE of the angle of R_est,aligned · R_gtᵀ
  std::size_t poses = 0;
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();
};
/// rpg compute_absolute_error on the estimate aligned by `alignment`.
AbsoluteError6Dof absoluteTrajectoryError6Dof(const PosePairs& pairs, TrajectoryAlignment alignment);

/// rpg's relative error over sub-trajectories of one length.
struct RelativeError {
  double distance = 0;  ///< the sub-trajectories' nominal length (m)
  std::size_t samples = 0;
  double trans_mean_m = kUndefinedError, trans_median_m = kUndefinedError, trans_rmse_m = kUndefinedError;
  double trans_mean_pct = kUndefinedError;    ///< the translation error over `distance`, mean, %
  double yaw_mean_deg = kUndefinedError;      ///< |yaw| of the error's z-y-x angles, mean
  double gravity_mean_deg = kUndefinedError;  ///< √(pitch² + roll²) of them, mean
  double rot_mean_deg = kUndefinedError;      ///< the error's rotation angle, mean
};
/// For each pose i, the later pose j whose ground-truth path length from i is nearest to
/// `distance` within `max_difference` (< 0: 0.2 · distance, rpg's); the error of the estimate's
/// motion i→j against the truth's, E = (T_gt,i⁻¹ T_gt,j)⁻¹ (T_est,i⁻¹ T_est,j), expressed in the
/// estimate's world axes (R_est,j E R_est,jᵀ) for its yaw and gravity angles. NaN with fewer than 2
/// samples (rpg computes nothing then).
RelativeError relativeError(const PosePairs& pairs, double distance, double max_difference = -1.0);

/// The final pose's position error after aligning the first pose by position and yaw (rpg's
/// posyaw with one frame), absolute and as a percentage of the ground truth's path length: what
/// radar-inertial papers report for sequences that end where they started.
struct FinalError {
  double final_m = kUndefinedError;
  double final_pct = kUndefinedError;
  double distance_m = 0;  ///< the ground truth's path length
};
FinalError finalPositionError(const PosePairs& pairs);

/// Without ground truth: how far the estimate ends from where it started, over its own path length
/// (%), for a sequence known to end at its start.
double loopClosureErrorPct(const std::vector<Eigen::Isometry3d>& poses);

}  // namespace radar_ndt
