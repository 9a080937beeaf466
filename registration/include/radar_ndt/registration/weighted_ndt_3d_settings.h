#pragma once
// The settings of radar_ndt::WeightedNDT3D in one struct, and what one align() found (as
// small_gicp's RegistrationSetting and RegistrationResult). The solve's constants mean what they
// mean for WeightedNDT2D (weighted_ndt_2d_settings.h); the defaults differ where a 4D radar's
// sparse scans and 3D cells ask for it. pcl::Registration's own settings (setMaximumIterations,
// setTransformationEpsilon, setTransformationRotationEpsilon) stay in the base class.

#include <cstddef>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "radar_ndt/fields.h"
#include "radar_ndt/registration/weighted_ndt_2d_result.h"
#include "radar_ndt/registration/weighted_ndt_2d_settings.h"

namespace radar_ndt {

struct WeightedNDT3DSettings {
  /// Cube sizes g (m), coarse to fine; each stage starts from the previous result.
  std::vector<float> resolutions{4.0f, 2.0f};
  /// Power shift s of eq. (1)-(2): weights max(p − s, 0).
  float power_shift = 0.0f;
  /// Whether the matching weights of eq. (2) use the shift too (the paper) or only the cells do.
  bool shift_source_weights = true;
  /// A cell's smallest covariance eigenvalues are raised to at least this ratio × its largest.
  double eigenvalue_ratio = 0.01;
  /// Cells built from fewer points are dropped.
  int min_points_per_cell = 3;
  /// Source points in one cube of this size (m) are merged into their weighted centroid carrying
  /// their summed weight before matching; 0 turns it off.
  double source_voxel_size = 0.25;
  /// Newton steps are limited to this translation (m; ≤ 0: half the grid size) and rotation
  /// (rad, > 0) before the line search.
  double max_step_translation = -1.0;
  double max_step_rotation = 0.2;
  /// Each grid stage first iterates on every k-th source point until its steps fall under the
  /// coarse epsilons, then finishes on all points; 1 turns the coarse phase off.
  int coarse_subsample = 4;
  /// Sources with fewer weighted points than this skip the coarse phase (a 4D radar's scan of a
  /// few dozen detections always does).
  int coarse_min_points = 256;
  double coarse_transformation_epsilon = 1e-4;
  double coarse_rotation_epsilon = 1e-3;
  /// A line search that improves nothing is converged when its Newton step lies within this
  /// fraction of the grid size and this rotation (rad); further away it is stuck.
  double stationary_translation_ratio = 0.05;
  double stationary_rotation = 0.01;
  double armijo = LineSearchDefaults::armijo;
  int max_halvings = LineSearchDefaults::max_halvings;
  double eigenvalue_floor = LineSearchDefaults::eigenvalue_floor;
  double negligible_decrease = LineSearchDefaults::negligible_decrease;
  /// Degenerate: fewer matched source points than this at the solution (six unknowns), or an
  /// information matrix whose smallest eigenvalue is below this ratio of its largest.
  int min_matched_points = 6;
  double min_information_ratio = 1e-9;

  /// Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void WeightedNDT3DSettings::fields(Visit&& visit) {
  using S = WeightedNDT3DSettings;
  visit(&S::resolutions, Field("resolutions", "cube sizes g, coarse to fine").unit("m").positive());
  visit(&S::power_shift, Field("power_shift", "s of eq. (1)-(2): weights max(p - s, 0)"));
  visit(&S::shift_source_weights,
        Field("shift_source_weights", "the matching weights of eq. (2) use the shift too (the paper)"));
  visit(&S::eigenvalue_ratio,
        Field("eigenvalue_ratio", "a cell's small covariance eigenvalues raised to this ratio of its largest")
            .positive()
            .atMost(1));
  visit(&S::min_points_per_cell, Field("min_points_per_cell", "cells of fewer points are dropped").atLeast(1));
  visit(&S::source_voxel_size,
        Field("source_voxel_size", "source points in one cube merged before matching; 0: off").unit("m").atLeast(0));
  visit(&S::max_step_translation,
        Field("max_step_translation", "a Newton step's largest translation; <= 0: half the grid size").unit("m"));
  visit(&S::max_step_rotation, Field("max_step_rotation", "a Newton step's largest rotation").unit("rad").positive());
  visit(
      &S::coarse_subsample,
      Field("coarse_subsample", "the coarse phase iterates on every k-th source point; 1: no coarse phase").atLeast(1));
  visit(&S::coarse_min_points,
        Field("coarse_min_points", "sources of fewer weighted points skip the coarse phase").atLeast(0));
  visit(&S::coarse_transformation_epsilon,
        Field("coarse_transformation_epsilon", "the coarse phase's squared translation epsilon").unit("m²").positive());
  visit(&S::coarse_rotation_epsilon,
        Field("coarse_rotation_epsilon", "the coarse phase's rotation epsilon").unit("rad").positive());
  visit(&S::stationary_translation_ratio,
        Field("stationary_translation_ratio", "a line search improving nothing converged within this share of g")
            .atLeast(0));
  visit(&S::stationary_rotation, Field("stationary_rotation", "... and within this rotation").unit("rad").atLeast(0));
  visit(&S::armijo, Field("armijo", "Armijo's sufficient-decrease factor").positive().below(1));
  visit(&S::max_halvings, Field("max_halvings", "trial steps of the line search, the full step first").atLeast(1));
  visit(
      &S::eigenvalue_floor,
      Field("eigenvalue_floor", "the Hessian's eigenvalues floored at this share of the largest").positive().below(1));
  visit(&S::negligible_decrease,
        Field("negligible_decrease", "a failed line search predicting less than this share of the cost converged")
            .atLeast(0));
  visit(&S::min_matched_points, Field("min_matched_points", "degenerate below this many matched points").atLeast(1));
  visit(&S::min_information_ratio,
        Field("min_information_ratio", "degenerate below this information eigenvalue ratio").atLeast(0).below(1));
}

/// Why the last align() stopped: the 2D matcher's statuses, the same names (toString).
using WeightedNDT3DStatus = WeightedNDT2DStatus;

/// What one WeightedNDT3D::align() found; getResult() returns it.
struct WeightedNDT3DResult {
  /// The source in the target's frame, as getFinalTransformation().
  Eigen::Matrix4f final_transformation = Eigen::Matrix4f::Identity();
  /// Converged and not degenerate: hasConverged().
  bool converged = false;
  WeightedNDT3DStatus status = WeightedNDT3DStatus::NotRun;
  /// Newton iterations, summed over coarse-to-fine stages and their subsampled phases.
  int iterations = 0;
  /// −Σ wᵢ exp(−½ qᵀΣ⁻¹q) on the finest grid at the solution (smaller is better).
  double final_cost = 0;
  /// Hessian of the cost at the solution in δ = (v, ω): the pose moved to (exp(ω) R, t + v), v
  /// and ω in the target's frame.
  Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
  /// Covariance of δ = (v, ω) (as the Hessian): the inverse of the weighted point-to-distribution
  /// information Σᵢ wᵢ eᵢ Jᵢᵀ Σ⁻¹ Jᵢ. Optimistic (points taken as independent); infinite diagonal
  /// and zero elsewhere when the problem is degenerate.
  Eigen::Matrix<double, 6, 6> pose_covariance = infiniteCovariance();
  /// Source points the cost used: finite, positive weight, after the voxel merge.
  std::size_t num_source_points = 0;
  /// Of those, the points that found at least one cell at the solution (finest grid).
  std::size_t num_matched_points = 0;

  bool degenerate() const { return status == WeightedNDT3DStatus::Degenerate; }
  /// The NDT score per source point used (NaN without source points).
  double scorePerPoint() const {
    return num_source_points == 0 ? std::numeric_limits<double>::quiet_NaN()
                                  : -final_cost / static_cast<double>(num_source_points);
  }
  static Eigen::Matrix<double, 6, 6> infiniteCovariance() {
    Eigen::Matrix<double, 6, 6> c = Eigen::Matrix<double, 6, 6>::Zero();
    c.diagonal().setConstant(std::numeric_limits<double>::infinity());
    return c;
  }
};

}  // namespace radar_ndt
