#pragma once
// What one WeightedNDT2D::align() found, in one struct (as small_gicp's RegistrationResult):
// returned by getResult() after align(). The pcl::Registration getters (getFinalTransformation,
// hasConverged, getFinalNumIteration) and the matcher's own getters read it.

#include <cstddef>
#include <limits>

#include <Eigen/Core>

namespace radar_ndt {

/// Why the last align() stopped.
enum class WeightedNDT2DStatus {
  NotRun,          ///< no align() yet
  Converged,       ///< a step below the epsilons, or a failed line search at the optimum (docs/matcher.md)
  Stuck,           ///< the line search found no improvement away from an optimum
  IterationLimit,  ///< setMaximumIterations reached in the last grid stage
  Degenerate,      ///< nothing to match, too few matched points, or a rank-deficient information matrix
};
/// "not-run", "converged", "stuck", "iteration-limit", "degenerate".
const char* toString(WeightedNDT2DStatus status);

struct WeightedNDT2DResult {
  /// The source in the target's frame (z = 0, rotation about z), as getFinalTransformation().
  Eigen::Matrix4f final_transformation = Eigen::Matrix4f::Identity();
  /// Converged and not degenerate: hasConverged().
  bool converged = false;
  WeightedNDT2DStatus status = WeightedNDT2DStatus::NotRun;
  /// Newton iterations, summed over coarse-to-fine stages and their subsampled phases.
  int iterations = 0;
  /// The cost at the solution, −Σ wᵢ exp(−½ qᵀΣ⁻¹q) on the finest grid (smaller is better); the NDT
  /// score of getNdtScore() is its negative.
  double final_cost = 0;
  /// Hessian of the cost at the solution, in (x, y, yaw).
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
  /// Covariance of (x, y, yaw): the inverse of the weighted point-to-distribution information
  /// Σᵢ wᵢ eᵢ Jᵢᵀ Σ⁻¹ Jᵢ (eᵢ the point's Gaussian score). Optimistic (treats points as independent);
  /// infinite diagonal and zero elsewhere when the problem is degenerate.
  Eigen::Matrix3d pose_covariance = infiniteCovariance();
  /// Source points the cost used: finite, positive weight, after the voxel merge.
  std::size_t num_source_points = 0;
  /// Of those, the points that found at least one cell at the solution (finest grid).
  std::size_t num_matched_points = 0;

  bool degenerate() const { return status == WeightedNDT2DStatus::Degenerate; }
  /// The NDT score Σ wᵢ exp(−½ qᵀΣ⁻¹q) per source point used (NaN without source points): comparable
  /// between scans of one sequence, a scan that fits its target nowhere scores a fraction of usual.
  double scorePerPoint() const {
    return num_source_points == 0 ? std::numeric_limits<double>::quiet_NaN()
                                  : -final_cost / static_cast<double>(num_source_points);
  }
  static Eigen::Matrix3d infiniteCovariance() {
    Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
    c.diagonal().setConstant(std::numeric_limits<double>::infinity());
    return c;
  }
};

}  // namespace radar_ndt
