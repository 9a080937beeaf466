#pragma once
// Implementation of radar_ndt::WeightedNDT2D: the pcl::Registration contract on top of the target
// model (detail/ndt_grid.h), the weighted source (detail/source_points.h), the cost
// (detail/ndt_cost.h) and the optimiser (detail/newton_optimizer.h). Included by the library's
// instantiation unit, and by users who need point types other than pcl::PointXYZ,
// pcl::PointXYZI and radar_ndt::PointRadar.

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include <pcl/common/transforms.h>
#include <pcl/console/print.h>

#include "radar_ndt/registration/detail/lazy_kdtree.h"
#include "radar_ndt/registration/detail/ndt_cost.h"
#include "radar_ndt/registration/detail/newton_optimizer.h"
#include "radar_ndt/registration/weighted_ndt_2d.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

template <typename PointSource, typename PointTarget>
WeightedNDT2D<PointSource, PointTarget>::WeightedNDT2D() {
  reg_name_ = "WeightedNDT2D";
  max_iterations_ = 35;
  transformation_epsilon_ = 1e-6;                     // (1 mm)² of translation increment
  transformation_rotation_epsilon_ = std::cos(1e-4);  // 0.1 mrad of rotation increment
  this->tree_.reset(new detail::LazyKdTree<PointTarget>());
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setInputSource(const typename PointCloudSource::ConstPtr& cloud) {
  if (cloud && !cloud->empty()) {
    Base::setInputSource(cloud);
    return;
  }
  // pcl::Registration refuses an empty cloud and keeps the previous one, which align() would then
  // match again as if nothing happened; take it, so align() reports the degenerate problem.
  this->source_cloud_updated_ = true;
  pcl::PCLBase<PointSource>::setInputCloud(cloud ? cloud : typename PointCloudSource::ConstPtr(new PointCloudSource));
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setInputTarget(const PointCloudTargetConstPtr& cloud) {
  if (cloud && !cloud->empty()) {
    Base::setInputTarget(cloud);
  } else {  // as for the source: an empty target, not the previous one
    target_ = cloud ? cloud : PointCloudTargetConstPtr(new PointCloudTarget);
    this->target_cloud_updated_ = true;
  }
  buildTargetModel();
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setMaxStep(double translation_m, double rotation_rad) {
  if (!(rotation_rad > 0.0) || !std::isfinite(rotation_rad) || !std::isfinite(translation_m)) {
    PCL_ERROR(
        "[radar_ndt::%s::setMaxStep] the rotation limit must be positive and finite and the translation finite "
        "(<= 0: half the grid); keeping the old ones\n",
        reg_name_.c_str());
    return;
  }
  settings_.max_step_translation = translation_m;
  settings_.max_step_rotation = rotation_rad;
}

template <typename PointSource, typename PointTarget>
double WeightedNDT2D<PointSource, PointTarget>::rotationEpsilon() const {
  return transformation_rotation_epsilon_ > 0 ? transformation_rotation_epsilon_ : 1.0 - transformation_epsilon_;
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setSettings(const WeightedNDT2DSettings& settings) {
  settings.validate();
  settings_ = settings;
  model_stale_ = true;  // rebuilt at the next setInputTarget() or align()
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setResolutions(const std::vector<float>& sizes) {
  if (sizes.empty() ||
      std::any_of(sizes.begin(), sizes.end(), [](float g) { return !(g > 0.0f) || !std::isfinite(g); })) {
    PCL_ERROR("[radar_ndt::%s::setResolutions] grid sizes must be positive and finite; keeping the old ones\n",
              reg_name_.c_str());
    return;
  }
  settings_.resolutions = sizes;
  model_stale_ = true;  // rebuilt at the next setInputTarget() or align()
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setPowerShift(float s) {
  if (!std::isfinite(s)) {
    PCL_ERROR("[radar_ndt::%s::setPowerShift] shift must be finite\n", reg_name_.c_str());
    return;
  }
  settings_.power_shift = s;
  model_stale_ = true;  // rebuilt at the next setInputTarget() or align()
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setEigenvalueRatio(double ratio) {
  if (!(ratio > 0.0 && ratio <= 1.0)) {
    PCL_ERROR("[radar_ndt::%s::setEigenvalueRatio] ratio must be in (0, 1]\n", reg_name_.c_str());
    return;
  }
  settings_.eigenvalue_ratio = ratio;
  model_stale_ = true;  // rebuilt at the next setInputTarget() or align()
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setMinPointsPerCell(int n) {
  settings_.min_points_per_cell = std::max(1, n);
  model_stale_ = true;  // rebuilt at the next setInputTarget() or align()
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setCellLookup(CellLookup lookup) {
  settings_.cell_lookup = lookup;
  model_stale_ = true;  // rebuilt at the next setInputTarget() or align()
}

template <typename PointSource, typename PointTarget>
std::size_t WeightedNDT2D<PointSource, PointTarget>::getTargetModelBytes() const {
  std::size_t bytes = 0;
  for (const auto& g : grids_) bytes += g.memoryBytes();
  return bytes;
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::buildTargetModel() {
  grids_.clear();
  model_stale_ = false;
  if (!target_) return;
  grids_.resize(settings_.resolutions.size());
  for (std::size_t i = 0; i < settings_.resolutions.size(); ++i)
    detail::buildNdtGrid(*target_, settings_.resolutions[i], settings_, grids_[i]);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::prepareSource() {
  source_points_.clear();
  if (!input_) return;
  // eq. (2): w = max(p − s, 0) · exp(−½(σx + σy)); s = 0 here with setShiftSourceWeights(false)
  const double source_shift = settings_.shift_source_weights ? settings_.power_shift : 0.0f;
  detail::weightSourcePoints(*input_, *this->indices_, source_shift, source_points_);
  detail::mergeSourceVoxels(settings_.source_voxel_size, source_points_, voxel_scratch_);
}

namespace detail {
/// What the finest grid's full-resolution phase also computes with each derivative evaluation,
/// for the diagnostics after the solve.
struct NdtDiagnostics {
  std::size_t matched = 0;
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
};
}  // namespace detail

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::computeTransformation(PointCloudSource& output, const Matrix4& guess) {
  converged_ = false;
  degenerate_ = false;
  final_num_iterations_ = 0;
  num_matched_points_ = 0;
  final_score_ = 0;
  final_hessian_.setZero();
  pose_covariance_.setZero();
  pose_covariance_.diagonal().setConstant(std::numeric_limits<double>::infinity());

  Pose2 x = toPose2(guess);
  if (!x.allFinite()) {
    PCL_ERROR("[radar_ndt::%s::computeTransformation] the initial guess is not finite\n", reg_name_.c_str());
    x.setZero();
  }
  if (model_stale_) buildTargetModel();
  prepareSource();

  auto finish = [&](const Pose2& pose) {
    final_transformation_ = transformation_ = toMatrix4<float>(pose);
    pcl::transformPointCloud(output, output, final_transformation_);
    if constexpr (pcl::traits::has_field<PointSource, pcl::fields::cov_xx>::value) {
      const Eigen::Matrix2d R = Eigen::Rotation2Dd(pose.z()).toRotationMatrix();
      for (auto& p : output) detail::rotateCovariance(p, R);
    }
    nr_iterations_ = final_num_iterations_;
  };

  if (grids_.empty() || grids_.back().cells.empty() || source_points_.empty()) {
    // Not an error of the call: the data left nothing to match (e.g. Doppler weights that agree
    // with no point, in the source or in the target: the last cycle's weighted submap). hasConverged()
    // and wasDegenerate() report it, as for too few matched points below, without a message a scan.
    PCL_DEBUG(
        "[radar_ndt::%s::computeTransformation] degenerate problem: %zu target cells, %zu weighted source "
        "points\n",
        reg_name_.c_str(), grids_.empty() ? std::size_t(0) : grids_.back().cells.size(), source_points_.size());
    degenerate_ = true;
    finish(x);
    return;
  }

  // Far from the optimum precision does not matter: each stage first iterates on a deterministic
  // 1-in-kSubsample subsample of the source (every k-th point in voxel order, spread over the
  // scan) until its steps fall under 1 cm and 1 mrad, then finishes on all points with the user's
  // epsilons. The fine phase starts close to the optimum and needs few Newton steps.
  constexpr std::size_t kSubsample = 4;
  const bool coarse_phase = source_points_.size() >= 16 * kSubsample;
  bool stage_converged = false;
  // The finest grid's full-resolution phase evaluates, with the information matrix and matched
  // count, every x it moves to (the final x may be a step below the epsilons further on), so the
  // diagnostics below need no extra pass.
  detail::NewtonState<detail::NdtDiagnostics> final_state;
  for (const auto& grid : grids_) {
    const bool finest = &grid == &grids_.back();
    const detail::StepLimit limit{
        settings_.max_step_translation > 0 ? settings_.max_step_translation : 0.5 * grid.resolution,
        settings_.max_step_rotation};
    int stage_iterations = 0;  // setMaximumIterations bounds both phases of a stage together
    for (int phase = coarse_phase ? 0 : 1; phase < 2; ++phase) {
      const std::size_t stride = phase == 0 ? kSubsample : 1;
      const detail::StepTolerance tolerance{
          phase == 0 ? std::max(1e-4, transformation_epsilon_) : transformation_epsilon_,
          phase == 0 ? std::min(std::cos(1e-3), rotationEpsilon()) : rotationEpsilon()};
      const bool diagnose = finest && phase == 1;  // also compute what the diagnostics need
      auto cost = [&](const Eigen::Vector3d& at, Eigen::Vector3d* g, Eigen::Matrix3d* H, detail::NdtDiagnostics* d) {
        const bool with = diagnose && d;
        return detail::ndtCost(grid, source_points_, at, g, H, with ? &d->matched : nullptr,
                               with ? &d->information : nullptr, stride);
      };
      detail::NewtonState<detail::NdtDiagnostics> state;
      // A line search that fails within 5 % of a cell of the Newton model's optimum is at the
      // optimum to the score's resolution; further away it is stuck.
      const detail::StationaryRegion stationary{0.05 * grid.resolution, 0.01};
      stage_converged = detail::minimizeNewton(cost, x, state, tolerance, limit, stationary, max_iterations_,
                                               &stage_iterations, &final_num_iterations_);
      if (diagnose) final_state = state;
    }
  }

  // Final diagnostics on the finest grid, from the loop's last evaluation there.
  final_score_ = -final_state.f;
  final_hessian_ = final_state.H;
  num_matched_points_ = final_state.extra.matched;
  const Eigen::Matrix3d& info = final_state.extra.information;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(info);
  const double imax = es.eigenvalues().maxCoeff(), imin = es.eigenvalues().minCoeff();
  if (num_matched_points_ < 3 || !(imax > 0) || !(imin > 1e-9 * imax)) {
    degenerate_ = true;
    PCL_DEBUG(
        "[radar_ndt::%s::computeTransformation] degenerate: %zu matched points, information eigenvalues "
        "%g..%g\n",
        reg_name_.c_str(), num_matched_points_, imin, imax);
  } else {
    pose_covariance_ = info.inverse();
  }
  converged_ = stage_converged && !degenerate_;
  finish(x);
}

}  // namespace radar_ndt
