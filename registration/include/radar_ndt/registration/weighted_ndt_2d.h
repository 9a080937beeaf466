#pragma once
// radar_ndt::WeightedNDT2D: the weighted probabilistic 2D NDT of the paper (Section III-C/D) as a
// pcl::Registration subclass, so it swaps with pcl::IterativeClosestPoint and
// pcl::NormalDistributionsTransform through a pcl::Registration<...>::Ptr.
//
// Target model (built once, in setInputTarget): square cells of side g; per cell the weighted mean
// μ = Σ wᵢpᵢ / Σ wᵢ and the probabilistic covariance Σ = Σ wᵢ[(pᵢ−μ)(pᵢ−μ)ᵀ + Σᵢ] / Σ wᵢ
// (Hong & Lee 2017), weights wᵢ = max(pᵢ − s, 0) (eq. 1), Σᵢ the point's own covariance.
// Cost: each source point scored against the cells near it, score = Σ wᵢ exp(−½ qᵀ Σ⁻¹ q) with
// q = T(x)pᵢ − μ and wᵢ = max(pᵢ − s, 0) · exp(−½(σx + σy)) (eq. 2); maximised by Newton's method on
// SE(2) with the analytic gradient and Hessian (Biber & Straßer 2003).
// Where each part lives: the settings in weighted_ndt_2d_settings.h, what align() found in
// weighted_ndt_2d_result.h (getResult()); the target model in
// detail/ndt_grid.h, the weighted source points in detail/source_points.h, the cost in
// detail/ndt_cost.h and the optimiser in detail/newton_optimizer.h; impl/ joins them.
//
// Point types: radar_ndt::PointRadar (power, covariance), pcl::PointXYZI (intensity = power, no
// covariance), pcl::PointXYZ (power 1, no covariance); fields are detected at compile time. The
// template is compiled once in the library for these three; for other point types include
// <radar_ndt/registration/impl/weighted_ndt_2d.hpp>.

#include <algorithm>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <pcl/point_types.h>
#include <pcl/registration/registration.h>

#include "radar_ndt/point_types.h"
#include "radar_ndt/registration/detail/ndt_grid.h"
#include "radar_ndt/registration/detail/newton_optimizer.h"
#include "radar_ndt/registration/detail/source_points.h"
#include "radar_ndt/registration/detail/sweep_cost.h"
#include "radar_ndt/registration/weighted_ndt_2d_result.h"
#include "radar_ndt/registration/weighted_ndt_2d_settings.h"

namespace radar_ndt {

template <typename PointSource, typename PointTarget>
class WeightedNDT2D : public pcl::Registration<PointSource, PointTarget, float> {
 public:
  using Base = pcl::Registration<PointSource, PointTarget, float>;
  using typename Base::Matrix4;
  using typename Base::PointCloudSource;
  using typename Base::PointCloudTarget;
  using PointCloudTargetConstPtr = typename PointCloudTarget::ConstPtr;
  using Ptr = pcl::shared_ptr<WeightedNDT2D<PointSource, PointTarget>>;
  using ConstPtr = pcl::shared_ptr<const WeightedNDT2D<PointSource, PointTarget>>;

  WeightedNDT2D();
  ~WeightedNDT2D() override = default;

  /// Sets the source scan. An empty (or null) cloud is taken as given: the next align() reports a
  /// degenerate problem (pcl::Registration would keep the previous source instead).
  void setInputSource(const typename PointCloudSource::ConstPtr& cloud) override;
  /// Sets the target and builds its cell model (all grid sizes), once per target. An empty (or
  /// null) cloud is taken as given, as for the source. The setters
  /// below that change the model (grid sizes, power shift, eigenvalue ratio, minimum points, cell
  /// lookup) only mark it stale: it is rebuilt once, at the next setInputTarget() or align(), so
  /// changing settings and target together costs one build.
  void setInputTarget(const PointCloudTargetConstPtr& cloud) override;

  /// Every setting below at once (validated: std::invalid_argument names the first one out of
  /// range); the model is rebuilt at the next setInputTarget() or align().
  void setSettings(const WeightedNDT2DSettings& settings);
  const WeightedNDT2DSettings& getSettings() const { return settings_; }

  // Each setter below writes one field of WeightedNDT2DSettings and validates the result: a value
  // out of range throws std::invalid_argument naming the field and changes nothing, as
  // setSettings() does (docs/matcher.md).

  /// Grid size g (m), single stage. Default 3.0 m.
  void setResolution(float g) { setResolutions({g}); }
  /// Coarse-to-fine grid sizes (e.g. {9, 6, 4}); each stage starts from the previous result.
  void setResolutions(const std::vector<float>& sizes);
  const std::vector<float>& getResolutions() const { return settings_.resolutions; }
  float getResolution() const { return settings_.resolutions.back(); }

  /// Power shift s of eq. (1)-(2): weights max(p − s, 0). Default 0.
  void setPowerShift(float s);
  float getPowerShift() const { return settings_.power_shift; }
  /// Whether the matching weights of eq. (2) use the shift too (the paper, and the default) or are
  /// p·exp(−½(σx + σy)) with the shift kept for the cells of eq. (1) only (an ablation).
  void setShiftSourceWeights(bool on);
  bool getShiftSourceWeights() const { return settings_.shift_source_weights; }

  /// A cell's smallest covariance eigenvalue is raised to at least ratio × its largest. Default 0.01.
  void setEigenvalueRatio(double ratio);
  double getEigenvalueRatio() const { return settings_.eigenvalue_ratio; }

  /// Cells built from fewer points are dropped (≥ 1). Default 3.
  void setMinPointsPerCell(int n);
  int getMinPointsPerCell() const { return settings_.min_points_per_cell; }

  /// Source points falling in one voxel of this size (m) are merged into one point at their
  /// weighted centroid carrying their summed weight, before matching. 0 turns it off. Default
  /// 0.25 m: small against the cells' spread, it leaves the cost almost unchanged and cuts the
  /// evaluation time with the point count.
  void setSourceVoxelSize(double size_m);
  double getSourceVoxelSize() const { return settings_.source_voxel_size; }

  void setCellLookup(CellLookup lookup);
  CellLookup getCellLookup() const { return settings_.cell_lookup; }

  /// Newton steps are limited to this translation (m; ≤ 0: half the grid size, the default) and
  /// rotation (rad, default 0.2; positive and finite, or no step could be taken) before the line
  /// search.
  void setMaxStep(double translation_m, double rotation_rad);

  /// The source sweep's own motion inside the match (docs/matcher.md): each source point is
  /// placed by x ⊕ m^α instead of x, where m is the constant-velocity motion over the step of
  /// `interval_s` seconds from the previous scan's reference time, at `previous_pose` (x, y, yaw in
  /// the target's frame), to the source's, and α the point's time offset (the `time_offset`
  /// field; 0 for types without one) over `interval_s`. The estimated motion and the de-skew of
  /// the source are then one unknown. Holds for every align() until clearSourceSweep(). Throws
  /// std::invalid_argument for an interval not positive and finite or a pose not finite.
  void setSourceSweep(double interval_s, const Eigen::Vector3d& previous_pose);
  /// Back to one rigid pose for the whole source (the default).
  void clearSourceSweep() { sweep_on_ = false; }
  bool hasSourceSweep() const { return sweep_on_; }

  /// Everything the last align() found: transform, convergence and why it stopped, iterations,
  /// cost, Hessian, pose covariance, source and matched points (WeightedNDT2DResult).
  const WeightedNDT2DResult& getResult() const { return result_; }

  /// Newton iterations of the last align(), summed over coarse-to-fine stages (PCL NDT's name).
  /// setMaximumIterations() bounds the iterations of each grid stage (default 35); a stage first
  /// iterates on a subsample of the source, then on all points, within that one budget.
  int getFinalNumIteration() const { return result_.iterations; }
  /// Hessian of the negative NDT score at the solution, in (x, y, yaw).
  const Eigen::Matrix3d& getFinalHessian() const { return result_.hessian; }
  /// 3x3 covariance of (x, y, yaw) (WeightedNDT2DResult::pose_covariance).
  const Eigen::Matrix3d& getPoseCovariance() const { return result_.pose_covariance; }
  /// Source points that found at least one cell at the solution (last stage).
  std::size_t getNumMatchedPoints() const { return result_.num_matched_points; }
  /// Final NDT score Σ wᵢ exp(−½ qᵀΣ⁻¹q) (larger is better). pcl::Registration::getFitnessScore()
  /// keeps PCL's meaning (mean squared nearest-neighbour distance) and builds a kd-tree to get it.
  double getNdtScore() const { return 0.0 - result_.final_cost; }
  /// Source points the cost uses: finite, positive weight, after the voxel merge.
  std::size_t getNumSourcePoints() const { return result_.num_source_points; }
  /// Cells in the target model of the finest grid, and its memory (bytes), as last built.
  std::size_t getNumCells() const { return grids_.empty() ? 0 : grids_.back().cells.size(); }
  std::size_t getTargetModelBytes() const;
  /// True when the last align() stopped because the problem was degenerate (too few matched
  /// points, a rank-deficient Hessian, no target cells, an empty source or target).
  bool wasDegenerate() const { return result_.degenerate(); }

 protected:
  using Base::converged_;
  using Base::final_transformation_;
  using Base::input_;
  using Base::max_iterations_;
  using Base::nr_iterations_;
  using Base::previous_transformation_;
  using Base::reg_name_;
  using Base::target_;
  using Base::transformation_;
  using Base::transformation_epsilon_;
  using Base::transformation_rotation_epsilon_;

  void computeTransformation(PointCloudSource& output, const Matrix4& guess) override;

  void buildTargetModel();
  /// The rotation epsilon the solve uses: setTransformationRotationEpsilon's when positive, else
  /// 1 − the transformation epsilon, as pcl::IterativeClosestPoint reads it.
  double rotationEpsilon() const;
  void prepareSource();
  /// Applies `change` to a copy of the settings, validates it and keeps it; `model`: the change
  /// invalidates the target model (rebuilt at the next setInputTarget() or align()).
  template <typename Change>
  void changeSettings(Change&& change, bool model);
  /// The Newton settings of one phase of a stage on `grid` (phase 0: the subsampled one).
  detail::NewtonSettings newtonSettings(const detail::NdtGrid& grid, int phase, int iterations_left) const;
  /// Every grid stage from `x`, coarse to fine; the result's iterations and status are set, and
  /// `final_state` holds the finest grid's last evaluation with the diagnostics.
  template <typename State>
  void solveStages(Eigen::Vector3d& x, State& final_state);
  /// Cost, Hessian, matched points, covariance and degeneracy from the finest grid's last evaluation.
  template <typename State>
  void diagnose(const State& final_state);
  /// Sets the result's transform (and PCL's) to `x` and moves `output`, the source as
  /// pcl::Registration::align() copied it, there.
  void finish(PointCloudSource& output, const Eigen::Vector3d& x);
  /// finish() for a source sweep: each point of `output` placed by x ⊕ m^α.
  void placeSweptOutput(PointCloudSource& output, const Eigen::Vector3d& x);

  WeightedNDT2DSettings settings_;
  std::vector<detail::NdtGrid> grids_;  // one per resolution, coarse to fine
  bool model_stale_ = false;            // a setting changed since grids_ was built
  std::vector<detail::WeightedPoint2D> source_points_;
  bool sweep_on_ = false;  // setSourceSweep(): each point placed by its time in the sweep
  detail::SweepStep sweep_;
  detail::SourceVoxelScratch voxel_scratch_;
  WeightedNDT2DResult result_;
};

}  // namespace radar_ndt

// The library compiles the template for these; others include impl/weighted_ndt_2d.hpp.
#ifndef RADAR_NDT_WEIGHTED_NDT_2D_INSTANTIATE
extern template class radar_ndt::WeightedNDT2D<pcl::PointXYZ, pcl::PointXYZ>;
extern template class radar_ndt::WeightedNDT2D<pcl::PointXYZI, pcl::PointXYZI>;
extern template class radar_ndt::WeightedNDT2D<radar_ndt::PointRadar, radar_ndt::PointRadar>;
// PCL templates for PointRadar that PCL does not precompile; compiled once in the library.
extern template class pcl::PCLBase<radar_ndt::PointRadar>;
extern template class pcl::search::KdTree<radar_ndt::PointRadar>;
extern template class pcl::Registration<radar_ndt::PointRadar, radar_ndt::PointRadar, float>;
#endif
