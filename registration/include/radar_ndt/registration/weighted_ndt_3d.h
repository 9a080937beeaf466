#pragma once
// radar_ndt::WeightedNDT3D: the weighted probabilistic NDT of the paper (Section III-C/D) in 3D,
// for 4D radars (x, y, z, Doppler, power), as a pcl::Registration subclass: it swaps with
// pcl::NormalDistributionsTransform, pcl::GeneralizedIterativeClosestPoint and
// pcl::IterativeClosestPoint through a pcl::Registration<...>::Ptr.
//
// Target model (built once, in setInputTarget): cubic cells of side g; per cell the weighted mean
// μ = Σ wᵢpᵢ / Σ wᵢ and the probabilistic covariance Σ = Σ wᵢ[(pᵢ−μ)(pᵢ−μ)ᵀ + Σᵢ] / Σ wᵢ, weights
// wᵢ = max(pᵢ − s, 0) (eq. 1), Σᵢ the point's own 3x3 covariance (a 4D radar's coarse elevation
// makes it tall: radar_ndt/frontend/point_covariance.h, sphericalCovariance).
// Cost: each source point scored against the 2x2x2 block of cells nearest to it,
// score = Σ wᵢ exp(−½ dᵀΣ⁻¹d) with d = R pᵢ + t − μ and wᵢ = max(pᵢ − s, 0) · exp(−½(σx + σy + σz))
// (eq. 2); maximised by Newton's method on SE(3) with the analytic gradient and Hessian
// (detail/ndt_cost_3d.h), the same optimiser as WeightedNDT2D (detail/newton_optimizer.h).
//
// Point types: radar_ndt::PointRadar4D (power, 3x3 covariance), pcl::PointXYZI (intensity =
// power), pcl::PointXYZ (power 1); compiled once in the library for these three; for other point
// types include <radar_ndt/registration/impl/weighted_ndt_3d.hpp>.

#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <pcl/point_types.h>
#include <pcl/registration/registration.h>

#include "radar_ndt/point_types.h"
#include "radar_ndt/registration/detail/ndt_grid_3d.h"
#include "radar_ndt/registration/detail/newton_optimizer.h"
#include "radar_ndt/registration/weighted_ndt_3d_settings.h"
#include "radar_ndt/se3.h"

namespace radar_ndt {

template <typename PointSource, typename PointTarget>
class WeightedNDT3D : public pcl::Registration<PointSource, PointTarget, float> {
 public:
  using Base = pcl::Registration<PointSource, PointTarget, float>;
  using typename Base::Matrix4;
  using typename Base::PointCloudSource;
  using typename Base::PointCloudTarget;
  using PointCloudTargetConstPtr = typename PointCloudTarget::ConstPtr;
  using Ptr = pcl::shared_ptr<WeightedNDT3D<PointSource, PointTarget>>;
  using ConstPtr = pcl::shared_ptr<const WeightedNDT3D<PointSource, PointTarget>>;

  WeightedNDT3D();
  ~WeightedNDT3D() override = default;

  /// Sets the source scan. An empty (or null) cloud is taken as given: the next align() reports a
  /// degenerate problem (pcl::Registration would keep the previous source instead).
  void setInputSource(const typename PointCloudSource::ConstPtr& cloud) override;
  /// Sets the target and builds its cell model (all grid sizes), once per target; an empty cloud
  /// as for the source. Setters that change the model only mark it stale: it is rebuilt once, at
  /// the next setInputTarget() or align().
  void setInputTarget(const PointCloudTargetConstPtr& cloud) override;

  /// Every setting at once (validated: std::invalid_argument names the first one out of range).
  void setSettings(const WeightedNDT3DSettings& settings);
  const WeightedNDT3DSettings& getSettings() const { return settings_; }

  // Each setter writes one field of WeightedNDT3DSettings and validates the result; a value out of
  // range throws std::invalid_argument naming the field and changes nothing.

  /// Cube size g (m), single stage (PCL NDT's name). Default: two stages, 4 m then 2 m.
  void setResolution(float g) { setResolutions({g}); }
  /// Coarse-to-fine cube sizes; each stage starts from the previous result.
  void setResolutions(const std::vector<float>& sizes);
  const std::vector<float>& getResolutions() const { return settings_.resolutions; }
  float getResolution() const { return settings_.resolutions.back(); }
  /// Power shift s of eq. (1)-(2): weights max(p − s, 0). Default 0.
  void setPowerShift(float s);
  float getPowerShift() const { return settings_.power_shift; }
  /// Source points in one cube of this size (m) merged before matching; 0 turns it off.
  void setSourceVoxelSize(double size_m);
  double getSourceVoxelSize() const { return settings_.source_voxel_size; }
  /// A cell's small covariance eigenvalues are raised to at least ratio × its largest.
  void setEigenvalueRatio(double ratio);
  /// Cells built from fewer points are dropped (≥ 1).
  void setMinPointsPerCell(int n);
  /// Newton steps are limited to this translation (m; ≤ 0: half the grid size) and rotation (rad).
  void setMaxStep(double translation_m, double rotation_rad);

  /// Everything the last align() found (WeightedNDT3DResult).
  const WeightedNDT3DResult& getResult() const { return result_; }
  /// Newton iterations of the last align(), summed over stages (PCL NDT's name).
  int getFinalNumIteration() const { return result_.iterations; }
  /// 6x6 covariance of the pose perturbation (v, ω) (WeightedNDT3DResult::pose_covariance).
  const Eigen::Matrix<double, 6, 6>& getPoseCovariance() const { return result_.pose_covariance; }
  /// Final NDT score Σ wᵢ exp(−½ dᵀΣ⁻¹d) (larger is better); getFitnessScore() keeps PCL's meaning.
  double getNdtScore() const { return 0.0 - result_.final_cost; }
  std::size_t getNumMatchedPoints() const { return result_.num_matched_points; }
  std::size_t getNumSourcePoints() const { return result_.num_source_points; }
  /// Cells of the finest grid, and the target model's memory (bytes), as last built.
  std::size_t getNumCells() const { return grids_.empty() ? 0 : grids_.back().cells.size(); }
  std::size_t getTargetModelBytes() const;
  bool wasDegenerate() const { return result_.degenerate(); }

 protected:
  using Base::converged_;
  using Base::final_transformation_;
  using Base::input_;
  using Base::max_iterations_;
  using Base::nr_iterations_;
  using Base::reg_name_;
  using Base::target_;
  using Base::transformation_;
  using Base::transformation_epsilon_;
  using Base::transformation_rotation_epsilon_;

  void computeTransformation(PointCloudSource& output, const Matrix4& guess) override;

  void buildTargetModel();
  void prepareSource();
  double rotationEpsilon() const;
  template <typename Change>
  void changeSettings(Change&& change, bool model);
  detail::NewtonSettings newtonSettings(const detail::NdtGrid3D& grid, int phase, int iterations_left) const;
  template <typename State>
  void solveStages(Pose3& x, State& final_state);
  template <typename State>
  void diagnose(const State& final_state);
  void finish(PointCloudSource& output, const Pose3& x);

  WeightedNDT3DSettings settings_;
  std::vector<detail::NdtGrid3D> grids_;  // one per resolution, coarse to fine
  bool model_stale_ = false;
  std::vector<detail::TargetPoint3D> target_points_;  // buffers reused from target to target
  detail::GridScratch3D grid_scratch_;
  std::vector<detail::WeightedPoint3D> source_points_;
  detail::SourceScratch3D source_scratch_;
  WeightedNDT3DResult result_;
};

}  // namespace radar_ndt

#ifndef RADAR_NDT_WEIGHTED_NDT_3D_INSTANTIATE
extern template class radar_ndt::WeightedNDT3D<pcl::PointXYZ, pcl::PointXYZ>;
extern template class radar_ndt::WeightedNDT3D<pcl::PointXYZI, pcl::PointXYZI>;
extern template class radar_ndt::WeightedNDT3D<radar_ndt::PointRadar4D, radar_ndt::PointRadar4D>;
// PCL templates for PointRadar4D that PCL does not precompile; compiled once in the library.
extern template class pcl::PCLBase<radar_ndt::PointRadar4D>;
extern template class pcl::search::KdTree<radar_ndt::PointRadar4D>;
extern template class pcl::Registration<radar_ndt::PointRadar4D, radar_ndt::PointRadar4D, float>;
#endif
