#pragma once
// The settings of radar_ndt::WeightedNDT2D in one struct (as small_gicp's RegistrationSetting):
// every PCL-style setter of the matcher writes here, and setSettings() takes them all at once.
// The pcl::Registration contract's own settings (setMaximumIterations, setTransformationEpsilon,
// setTransformationRotationEpsilon) stay in the pcl::Registration base class.

#include <vector>

#include "radar_ndt/fields.h"

namespace radar_ndt {

/// How a source point finds the target distributions it is scored against.
enum class CellLookup {
  /// One grid; a point is scored against the 2x2 block of cells whose centres are nearest to it
  /// (the cell it falls in and the three neighbours on its side), as ndt_omp's direct search does.
  Neighbours,
  /// Biber's four overlapping grids, shifted by half a cell in x, y and both; a point is scored
  /// against the cell it falls in, in each grid.
  OverlappingGrids,
};
template <>
struct EnumNames<CellLookup> {
  static constexpr const char* what = "cell lookup";
  static constexpr EnumName<CellLookup> names[] = {
      {CellLookup::Neighbours, "neighbours", "the 2x2 block of cells nearest to the point"},
      {CellLookup::OverlappingGrids, "overlapping-grids", "Biber's four grids shifted by half a cell"}};
};

/// The line search's constants, one home each: WeightedNDT2DSettings starts from them, and so does
/// the optimiser's NewtonSettings (detail/newton_optimizer.h) when a test builds one alone.
struct LineSearchDefaults {
  static constexpr double armijo = 1e-4;
  static constexpr int max_halvings = 12;
  static constexpr double eigenvalue_floor = 1e-6;
  static constexpr double negligible_decrease = 1e-6;
};

struct WeightedNDT2DSettings {
  /// Grid sizes g (m), coarse to fine; each stage starts from the previous result.
  std::vector<float> resolutions{3.0f};
  /// Power shift s of eq. (1)-(2): weights max(p − s, 0).
  float power_shift = 0.0f;
  /// Whether the matching weights of eq. (2) use the shift too (the paper) or are
  /// p·exp(−½(σx + σy)) with the shift kept for the cells of eq. (1) only (an ablation).
  bool shift_source_weights = true;
  /// A cell's smallest covariance eigenvalue is raised to at least this ratio × its largest.
  double eigenvalue_ratio = 0.01;
  /// Cells built from fewer points are dropped.
  int min_points_per_cell = 3;
  CellLookup cell_lookup = CellLookup::Neighbours;
  /// Source points in one voxel of this size (m) are merged into their weighted centroid carrying
  /// their summed weight before matching; 0 turns it off. Small against the cells' spread, it
  /// leaves the cost almost unchanged and cuts the evaluation time with the point count.
  double source_voxel_size = 0.25;
  /// Newton steps are limited to this translation (m; ≤ 0: half the grid size) and rotation
  /// (rad, > 0) before the line search.
  double max_step_translation = -1.0;
  double max_step_rotation = 0.2;

  // The solve. PCL's own settings (setMaximumIterations, setTransformationEpsilon,
  // setTransformationRotationEpsilon) bound each grid stage and its final phase; these are the
  // rest of the loop's constants (docs/matcher.md).
  /// Far from the optimum precision does not matter: each grid stage first iterates on every k-th
  /// source point (in voxel order, spread over the scan) until its steps fall under the coarse
  /// epsilons, then finishes on all points. 1 turns the coarse phase off.
  int coarse_subsample = 4;
  /// Sources with fewer weighted points than this skip the coarse phase.
  int coarse_min_points = 64;
  /// The coarse phase's epsilons: squared translation (m², as PCL's transformation epsilon: 1 cm)
  /// and rotation (rad); the user's epsilons when those are looser.
  double coarse_transformation_epsilon = 1e-4;
  double coarse_rotation_epsilon = 1e-3;
  /// A line search that improves nothing is converged when the Newton step it started from lies
  /// within this fraction of the grid size and this rotation (rad): the model's optimum is within
  /// the score's resolution there. Further away it is stuck.
  double stationary_translation_ratio = 0.05;
  double stationary_rotation = 0.01;
  /// Armijo's sufficient-decrease factor of the line search, in (0, 1).
  double armijo = LineSearchDefaults::armijo;
  /// Trial steps of the line search: the full step and its halvings, at most this many in all.
  int max_halvings = LineSearchDefaults::max_halvings;
  /// The Hessian's eigenvalues are mirrored and floored at this fraction of the largest, in (0, 1).
  double eigenvalue_floor = LineSearchDefaults::eigenvalue_floor;
  /// A failed line search that predicts a decrease below this fraction of the cost is converged.
  double negligible_decrease = LineSearchDefaults::negligible_decrease;
  /// Degenerate: fewer matched source points than this at the solution, or an information matrix
  /// whose smallest eigenvalue is below this ratio of its largest.
  int min_matched_points = 3;
  double min_information_ratio = 1e-9;

  /// Throws std::invalid_argument naming the first setting out of range (the ranges are the
  /// field table's, below; docs/matcher.md lists them).
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void WeightedNDT2DSettings::fields(Visit&& visit) {
  using S = WeightedNDT2DSettings;
  visit(&S::resolutions, Field("resolutions", "grid sizes g, coarse to fine").unit("m").positive());
  visit(&S::power_shift, Field("power_shift", "s of eq. (1)-(2): weights max(p - s, 0)"));
  visit(&S::shift_source_weights,
        Field("shift_source_weights", "the matching weights of eq. (2) use the shift too (the paper)"));
  visit(&S::eigenvalue_ratio,
        Field("eigenvalue_ratio", "a cell's smallest covariance eigenvalue raised to this ratio of its largest")
            .positive()
            .atMost(1));
  visit(&S::min_points_per_cell, Field("min_points_per_cell", "cells of fewer points are dropped").atLeast(1));
  visit(&S::cell_lookup, Field("cell_lookup", "how a source point finds its target cells"));
  visit(&S::source_voxel_size,
        Field("source_voxel_size", "source points in one voxel merged before matching; 0: off").unit("m").atLeast(0));
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

}  // namespace radar_ndt
