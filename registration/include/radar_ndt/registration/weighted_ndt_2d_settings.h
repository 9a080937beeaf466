#pragma once
// The settings of radar_ndt::WeightedNDT2D in one struct (as small_gicp's RegistrationSetting):
// every PCL-style setter of the matcher writes here, and setSettings() takes them all at once.
// The pcl::Registration contract's own settings (setMaximumIterations, setTransformationEpsilon,
// setTransformationRotationEpsilon) stay in the pcl::Registration base class.

#include <vector>

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

  /// Throws std::invalid_argument naming the first setting out of range: resolutions empty, not
  /// positive or not finite; power_shift not finite; eigenvalue_ratio outside (0, 1];
  /// min_points_per_cell < 1; source_voxel_size negative or not finite; max_step_rotation ≤ 0 or
  /// not finite; max_step_translation not finite.
  void validate() const;
};

}  // namespace radar_ndt
