#pragma once
// Implementation of radar_ndt::WeightedNDT3D: the pcl::Registration contract on top of the target
// model and weighted source (detail/ndt_grid_3d.h), the cost (detail/ndt_cost_3d.h) and the
// optimiser (detail/newton_optimizer.h). Included by the library's instantiation unit, and by
// users who need point types other than pcl::PointXYZ, pcl::PointXYZI and PointRadar4D.

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <pcl/common/transforms.h>
#include <pcl/console/print.h>

#include "radar_ndt/registration/detail/lazy_kdtree.h"
#include "radar_ndt/registration/detail/ndt_cost_3d.h"
#include "radar_ndt/registration/weighted_ndt_3d.h"

namespace radar_ndt {

template <typename PointSource, typename PointTarget>
WeightedNDT3D<PointSource, PointTarget>::WeightedNDT3D() {
  reg_name_ = "WeightedNDT3D";
  max_iterations_ = 35;
  transformation_epsilon_ = 1e-6;                     // (1 mm)² of translation increment
  transformation_rotation_epsilon_ = std::cos(1e-4);  // 0.1 mrad of rotation increment
  this->tree_.reset(new detail::LazyKdTree<PointTarget>());
}

template <typename PointSource, typename PointTarget>
void WeightedNDT3D<PointSource, PointTarget>::setInputSource(const typename PointCloudSource::ConstPtr& cloud) {
  if (cloud && !cloud->empty()) {
    Base::setInputSource(cloud);
    return;
  }
  // pcl::Registration refuses an empty cloud and keeps the previous one; take it, so align()
  // reports the degenerate problem.
  this->source_cloud_updated_ = true;
  pcl::PCLBase<PointSource>::setInputCloud(cloud ? cloud : typename PointCloudSource::ConstPtr(new PointCloudSource));
}

template <typename PointSource, typename PointTarget>
void WeightedNDT3D<PointSource, PointTarget>::setInputTarget(const PointCloudTargetConstPtr& cloud) {
  if (cloud && !cloud->empty()) {
    Base::setInputTarget(cloud);
  } else {
    target_ = cloud ? cloud : PointCloudTargetConstPtr(new PointCloudTarget);
    this->target_cloud_updated_ = true;
  }
  buildTargetModel();
}

template <typename PointSource, typename PointTarget>
double WeightedNDT3D<PointSource, PointTarget>::rotationEpsilon() const {
  return transformation_rotation_epsilon_ > 0 ? transformation_rotation_epsilon_ : 1.0 - transformation_epsilon_;
}

template <typename PointSource, typename PointTarget>
template <typename Change>
void WeightedNDT3D<PointSource, PointTarget>::changeSettings(Change&& change, bool model) {
  WeightedNDT3DSettings changed = settings_;
  change(changed);
  changed.validate();  // throws, naming the field; nothing has changed then
  settings_ = std::move(changed);
  if (model) model_stale_ = true;
}

template <typename PointSource, typename PointTarget>
void WeightedNDT3D<PointSource, PointTarget>::setSettings(const WeightedNDT3DSettings& settings) {
  changeSettings([&](WeightedNDT3DSettings& s) { s = settings; }, true);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT3D<PointSource, PointTarget>::setResolutions(const std::vector<float>& sizes) {
  changeSettings([&](WeightedNDT3DSettings& s) { s.resolutions = sizes; }, true);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT3D<PointSource, PointTarget>::setPowerShift(float shift) {
  changeSettings([&](WeightedNDT3DSettings& s) { s.power_shift = shift; }, true);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT3D<PointSource, PointTarget>::setSourceVoxelSize(double size_m) {
  changeSettings([&](WeightedNDT3DSettings& s) { s.source_voxel_size = size_m; }, false);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT3D<PointSource, PointTarget>::setEigenvalueRatio(double ratio) {
  changeSettings([&](WeightedNDT3DSettings& s) { s.eigenvalue_ratio = ratio; }, true);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT3D<PointSource, PointTarget>::setMinPointsPerCell(int n) {
  changeSettings([&](WeightedNDT3DSettings& s) { s.min_points_per_cell = n; }, true);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT3D<PointSource, PointTarget>::setMaxStep(double translation_m, double rotation_rad) {
  changeSettings(
      [&](WeightedNDT3DSettings& s) {
        s.max_step_translation = translation_m;
        s.max_step_rotation = rotation_rad;
      },
      false);
}

template <typename PointSource, typename PointTarget>
std::size_t WeightedNDT3D<PointSource, PointTarget>::getTargetModelBytes() const {
  std::size_t bytes = 0;
  for (const auto& g : grids_) bytes += g.memoryBytes();
  return bytes;
}

template <typename PointSource, typename PointTarget>
void WeightedNDT3D<PointSource, PointTarget>::buildTargetModel() {
  model_stale_ = false;
  if (!target_) {
    grids_.clear();
    return;
  }
  // The grids and buffers keep their memory from target to target (an odometry's local maps keep
  // their sizes), so a new target allocates nothing.
  grids_.resize(settings_.resolutions.size());
  detail::weightTargetPoints3D(*target_, settings_.power_shift, target_points_);
  for (std::size_t i = 0; i < settings_.resolutions.size(); ++i)
    detail::buildNdtGrid3D(target_points_, settings_.resolutions[i], settings_, grids_[i], grid_scratch_);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT3D<PointSource, PointTarget>::prepareSource() {
  source_points_.clear();
  if (!input_) return;
  const double shift = settings_.shift_source_weights ? settings_.power_shift : 0.0f;
  detail::weightSourcePoints3D(*input_, *this->indices_, shift, source_points_);
  detail::mergeSourceVoxels3D(settings_.source_voxel_size, source_points_, source_scratch_);
}

namespace detail {
/// What the finest grid's full-resolution phase also computes, for the diagnostics.
struct NdtDiagnostics3D {
  std::size_t matched = 0;
  Matrix6d information = Matrix6d::Zero();
};
}  // namespace detail

template <typename PointSource, typename PointTarget>
void WeightedNDT3D<PointSource, PointTarget>::computeTransformation(PointCloudSource& output, const Matrix4& guess) {
  result_ = WeightedNDT3DResult{};
  Pose3 x = toPose3(guess);
  if (!allFinite(x)) {
    PCL_ERROR("[radar_ndt::%s::computeTransformation] the initial guess is not finite\n", reg_name_.c_str());
    x = Pose3::Identity();
  }
  if (model_stale_) buildTargetModel();
  prepareSource();
  result_.num_source_points = source_points_.size();
  if (grids_.empty() || grids_.back().cells.empty() || source_points_.empty()) {
    PCL_DEBUG("[radar_ndt::%s::computeTransformation] degenerate problem: %zu target cells, %zu source points\n",
              reg_name_.c_str(), grids_.empty() ? std::size_t(0) : grids_.back().cells.size(), source_points_.size());
    result_.status = WeightedNDT3DStatus::Degenerate;
    finish(output, x);
    return;
  }
  detail::NewtonState<detail::NdtDiagnostics3D, 6> final_state;
  solveStages(x, final_state);
  diagnose(final_state);
  finish(output, x);
}

template <typename PointSource, typename PointTarget>
detail::NewtonSettings WeightedNDT3D<PointSource, PointTarget>::newtonSettings(const detail::NdtGrid3D& grid, int phase,
                                                                               int iterations_left) const {
  const WeightedNDT3DSettings& s = settings_;
  detail::NewtonSettings n;
  n.tolerance = {
      phase == 0 ? std::max(s.coarse_transformation_epsilon, transformation_epsilon_) : transformation_epsilon_,
      phase == 0 ? std::min(std::cos(s.coarse_rotation_epsilon), rotationEpsilon()) : rotationEpsilon()};
  n.limit = {s.max_step_translation > 0 ? s.max_step_translation : 0.5 * grid.resolution, s.max_step_rotation};
  n.stationary = {s.stationary_translation_ratio * grid.resolution, s.stationary_rotation};
  n.max_iterations = iterations_left;
  n.eigenvalue_floor = s.eigenvalue_floor;
  n.armijo = s.armijo;
  n.max_halvings = s.max_halvings;
  n.negligible_decrease = s.negligible_decrease;
  return n;
}

template <typename PointSource, typename PointTarget>
template <typename State>
void WeightedNDT3D<PointSource, PointTarget>::solveStages(Pose3& x, State& final_state) {
  const std::size_t subsample = static_cast<std::size_t>(settings_.coarse_subsample);
  const bool coarse_phase =
      subsample > 1 && source_points_.size() >= static_cast<std::size_t>(settings_.coarse_min_points);
  detail::NewtonRun run;
  for (const auto& grid : grids_) {
    const bool finest = &grid == &grids_.back();
    int stage_iterations = 0;  // setMaximumIterations bounds both phases of a stage together
    for (int phase = coarse_phase ? 0 : 1; phase < 2; ++phase) {
      const std::size_t stride = phase == 0 ? subsample : 1;
      const bool diagnose = finest && phase == 1;
      auto cost = [&](const Pose3& at, Vector6d* g, Matrix6d* H, detail::NdtDiagnostics3D* d) {
        const bool with = diagnose && d;
        return detail::ndtCost3D(grid, source_points_, at, g, H, with ? &d->matched : nullptr,
                                 with ? &d->information : nullptr, stride);
      };
      State state;
      run = detail::minimizeNewton(cost, x, state, newtonSettings(grid, phase, max_iterations_ - stage_iterations));
      stage_iterations += run.iterations;
      result_.iterations += run.iterations;
      if (diagnose) final_state = state;
    }
  }
  switch (run.outcome) {
    case detail::NewtonOutcome::Converged: result_.status = WeightedNDT3DStatus::Converged; break;
    case detail::NewtonOutcome::Stuck: result_.status = WeightedNDT3DStatus::Stuck; break;
    case detail::NewtonOutcome::IterationLimit: result_.status = WeightedNDT3DStatus::IterationLimit; break;
    case detail::NewtonOutcome::NoDirection: result_.status = WeightedNDT3DStatus::Degenerate; break;
  }
}

template <typename PointSource, typename PointTarget>
template <typename State>
void WeightedNDT3D<PointSource, PointTarget>::diagnose(const State& final_state) {
  result_.final_cost = final_state.f;
  result_.hessian = final_state.H;
  result_.num_matched_points = final_state.extra.matched;
  const Matrix6d& info = final_state.extra.information;
  const Eigen::SelfAdjointEigenSolver<Matrix6d> es(info);
  const double imax = es.eigenvalues().maxCoeff(), imin = es.eigenvalues().minCoeff();
  if (result_.num_matched_points < static_cast<std::size_t>(settings_.min_matched_points) || !(imax > 0) ||
      !(imin > settings_.min_information_ratio * imax)) {
    result_.status = WeightedNDT3DStatus::Degenerate;
    PCL_DEBUG("[radar_ndt::%s::computeTransformation] degenerate: %zu matched points, information eigenvalues %g..%g\n",
              reg_name_.c_str(), result_.num_matched_points, imin, imax);
  } else {
    result_.pose_covariance = info.inverse();
  }
}

template <typename PointSource, typename PointTarget>
void WeightedNDT3D<PointSource, PointTarget>::finish(PointCloudSource& output, const Pose3& x) {
  result_.converged = result_.status == WeightedNDT3DStatus::Converged;
  result_.final_transformation = toMatrix4<float>(x);
  converged_ = result_.converged;
  final_transformation_ = transformation_ = result_.final_transformation;
  nr_iterations_ = result_.iterations;
  pcl::transformPointCloud(output, output, final_transformation_);
  if constexpr (pcl::traits::has_field<PointSource, pcl::fields::cov_zz>::value) {
    const Eigen::Matrix3d R = x.linear();
    for (auto& p : output) detail::rotateCovariance3D(p, R);
  }
}

}  // namespace radar_ndt
