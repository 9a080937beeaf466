#pragma once
// Implementation of radar_ndt::WeightedNDT2D: the pcl::Registration contract on top of the target
// model (detail/ndt_grid.h), the weighted source (detail/source_points.h), the cost
// (detail/ndt_cost.h) and the optimiser (detail/newton_optimizer.h). Included by the library's
// instantiation unit, and by users who need point types other than pcl::PointXYZ,
// pcl::PointXYZI and radar_ndt::PointRadar.

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>
#include <pcl/common/transforms.h>
#include <pcl/console/print.h>

#include "radar_ndt/registration/detail/lazy_kdtree.h"
#include "radar_ndt/registration/detail/ndt_cost.h"
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
double WeightedNDT2D<PointSource, PointTarget>::rotationEpsilon() const {
  return transformation_rotation_epsilon_ > 0 ? transformation_rotation_epsilon_ : 1.0 - transformation_epsilon_;
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setSettings(const WeightedNDT2DSettings& settings) {
  changeSettings([&](WeightedNDT2DSettings& s) { s = settings; }, true);
}

template <typename PointSource, typename PointTarget>
template <typename Change>
void WeightedNDT2D<PointSource, PointTarget>::changeSettings(Change&& change, bool model) {
  WeightedNDT2DSettings changed = settings_;
  change(changed);
  changed.validate();  // throws, naming the field; nothing has changed then
  settings_ = std::move(changed);
  if (model) model_stale_ = true;  // rebuilt at the next setInputTarget() or align()
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setResolutions(const std::vector<float>& sizes) {
  changeSettings([&](WeightedNDT2DSettings& s) { s.resolutions = sizes; }, true);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setPowerShift(float shift) {
  changeSettings([&](WeightedNDT2DSettings& s) { s.power_shift = shift; }, true);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setShiftSourceWeights(bool on) {
  changeSettings([&](WeightedNDT2DSettings& s) { s.shift_source_weights = on; }, false);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setEigenvalueRatio(double ratio) {
  changeSettings([&](WeightedNDT2DSettings& s) { s.eigenvalue_ratio = ratio; }, true);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setMinPointsPerCell(int n) {
  changeSettings([&](WeightedNDT2DSettings& s) { s.min_points_per_cell = n; }, true);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setSourceVoxelSize(double size_m) {
  changeSettings([&](WeightedNDT2DSettings& s) { s.source_voxel_size = size_m; }, false);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setCellLookup(CellLookup lookup) {
  changeSettings([&](WeightedNDT2DSettings& s) { s.cell_lookup = lookup; }, true);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setMaxStep(double translation_m, double rotation_rad) {
  changeSettings(
      [&](WeightedNDT2DSettings& s) {
        s.max_step_translation = translation_m;
        s.max_step_rotation = rotation_rad;
      },
      false);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setSourceSweep(double interval_s, const Eigen::Vector3d& previous_pose) {
  if (!(interval_s > 0) || !std::isfinite(interval_s))
    throw std::invalid_argument("WeightedNDT2D::setSourceSweep: the interval must be > 0 and finite, got " +
                                std::to_string(interval_s));
  if (!previous_pose.allFinite())
    throw std::invalid_argument("WeightedNDT2D::setSourceSweep: the previous pose is not finite");
  sweep_.dt = interval_s;
  sweep_.previous = previous_pose;
  sweep_on_ = true;
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
  if (sweep_on_ && settings_.source_voxel_size > 0)
    detail::mergeSourceVoxelsByHalfSweep(settings_.source_voxel_size, source_points_, voxel_scratch_);
  else
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
  result_ = WeightedNDT2DResult{};
  Pose2 x = toPose2(guess);
  if (!x.allFinite()) {
    PCL_ERROR("[radar_ndt::%s::computeTransformation] the initial guess is not finite\n", reg_name_.c_str());
    x.setZero();
  }
  if (model_stale_) buildTargetModel();
  prepareSource();
  result_.num_source_points = source_points_.size();

  if (grids_.empty() || grids_.back().cells.empty() || source_points_.empty()) {
    // Not an error of the call: the data left nothing to match (e.g. Doppler weights that agree
    // with no point, in the source or in the target: the last cycle's weighted submap). The result
    // reports it, as for too few matched points below, without a message a scan.
    PCL_DEBUG(
        "[radar_ndt::%s::computeTransformation] degenerate problem: %zu target cells, %zu weighted source "
        "points\n",
        reg_name_.c_str(), grids_.empty() ? std::size_t(0) : grids_.back().cells.size(), source_points_.size());
    result_.status = WeightedNDT2DStatus::Degenerate;
    finish(output, x);
    return;
  }
  // The finest grid's full-resolution phase evaluates, with the information matrix and matched
  // count, every x it moves to (the final x may be a step below the epsilons further on), so the
  // diagnostics need no extra pass.
  detail::NewtonState<detail::NdtDiagnostics> final_state;
  solveStages(x, final_state);
  diagnose(final_state);
  finish(output, x);
}

template <typename PointSource, typename PointTarget>
detail::NewtonSettings WeightedNDT2D<PointSource, PointTarget>::newtonSettings(const detail::NdtGrid& grid, int phase,
                                                                               int iterations_left) const {
  const WeightedNDT2DSettings& s = settings_;
  detail::NewtonSettings n;
  // Phase 0 stops at the coarse epsilons (or the user's, when looser); phase 1 at the user's.
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
void WeightedNDT2D<PointSource, PointTarget>::solveStages(Eigen::Vector3d& x, State& final_state) {
  const std::size_t subsample = static_cast<std::size_t>(settings_.coarse_subsample);
  const bool coarse_phase =
      subsample > 1 && source_points_.size() >= static_cast<std::size_t>(settings_.coarse_min_points);
  detail::NewtonRun run;
  for (const auto& grid : grids_) {
    const bool finest = &grid == &grids_.back();
    int stage_iterations = 0;  // setMaximumIterations bounds both phases of a stage together
    for (int phase = coarse_phase ? 0 : 1; phase < 2; ++phase) {
      const std::size_t stride = phase == 0 ? subsample : 1;
      const bool diagnose = finest && phase == 1;  // also compute what the diagnostics need
      auto cost = [&](const Eigen::Vector3d& at, Eigen::Vector3d* g, Eigen::Matrix3d* H, detail::NdtDiagnostics* d) {
        const bool with = diagnose && d;
        if (sweep_on_)
          return detail::ndtSweepCost(grid, source_points_, sweep_, at, g, H, with ? &d->matched : nullptr,
                                      with ? &d->information : nullptr, stride);
        return detail::ndtCost(grid, source_points_, at, g, H, with ? &d->matched : nullptr,
                               with ? &d->information : nullptr, stride);
      };
      State state;
      run = detail::minimizeNewton(cost, x, state, newtonSettings(grid, phase, max_iterations_ - stage_iterations));
      stage_iterations += run.iterations;
      result_.iterations += run.iterations;
      if (diagnose) final_state = state;
    }
  }
  switch (run.outcome) {  // the last phase's: the finest grid on all points
    case detail::NewtonOutcome::Converged: result_.status = WeightedNDT2DStatus::Converged; break;
    case detail::NewtonOutcome::Stuck: result_.status = WeightedNDT2DStatus::Stuck; break;
    case detail::NewtonOutcome::IterationLimit: result_.status = WeightedNDT2DStatus::IterationLimit; break;
    case detail::NewtonOutcome::NoDirection: result_.status = WeightedNDT2DStatus::Degenerate; break;
  }
}

template <typename PointSource, typename PointTarget>
template <typename State>
void WeightedNDT2D<PointSource, PointTarget>::diagnose(const State& final_state) {
  result_.final_cost = final_state.f;
  result_.hessian = final_state.H;
  result_.num_matched_points = final_state.extra.matched;
  const Eigen::Matrix3d& info = final_state.extra.information;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(info);
  const double imax = es.eigenvalues().maxCoeff(), imin = es.eigenvalues().minCoeff();
  if (result_.num_matched_points < static_cast<std::size_t>(settings_.min_matched_points) || !(imax > 0) ||
      !(imin > settings_.min_information_ratio * imax)) {
    result_.status = WeightedNDT2DStatus::Degenerate;
    PCL_DEBUG(
        "[radar_ndt::%s::computeTransformation] degenerate: %zu matched points, information eigenvalues "
        "%g..%g\n",
        reg_name_.c_str(), result_.num_matched_points, imin, imax);
  } else {
    result_.pose_covariance = info.inverse();
  }
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::finish(PointCloudSource& output, const Eigen::Vector3d& x) {
  result_.converged = result_.status == WeightedNDT2DStatus::Converged;
  result_.final_transformation = toMatrix4<float>(x);
  converged_ = result_.converged;
  final_transformation_ = transformation_ = result_.final_transformation;
  nr_iterations_ = result_.iterations;
  if (sweep_on_) {
    placeSweptOutput(output, x);
    return;
  }
  pcl::transformPointCloud(output, output, final_transformation_);
  if constexpr (pcl::traits::has_field<PointSource, pcl::fields::cov_xx>::value) {
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(x.z()).toRotationMatrix();
    for (auto& p : output) detail::rotateCovariance(p, R);
  }
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::placeSweptOutput(PointCloudSource& output, const Eigen::Vector3d& x) {
  // Each point where the cost placed it, x ⊕ m^α, rotated by θ + αφ; z is kept as
  // pcl::transformPointCloud keeps it for a planar transform.
  const double c = std::cos(x.z()), s = std::sin(x.z());
  const double phi = x.z() - sweep_.previous.z();
  const double ux = x.x() - sweep_.previous.x(), uy = x.y() - sweep_.previous.y();
  for (auto& p : output) {
    const double alpha = detail::pointTimeOffset(p) / sweep_.dt;
    const detail::SweepPlacement q = detail::placeInSweep(p.x, p.y, alpha, c, s, x.x(), x.y(), phi, ux, uy);
    p.x = static_cast<float>(q.qx);
    p.y = static_cast<float>(q.qy);
    if constexpr (pcl::traits::has_field<PointSource, pcl::fields::cov_xx>::value)
      detail::rotateCovariance(p, Eigen::Rotation2Dd(x.z() + alpha * phi).toRotationMatrix());
    if constexpr (pcl::traits::has_field<PointSource, pcl::fields::time_offset>::value)
      p.time_offset = 0.f;  // seen from the source's reference pose now, as compensateMotion leaves it
  }
}

}  // namespace radar_ndt
