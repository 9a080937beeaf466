#pragma once
// The paper's probabilistic radar submap (Sec. III-B): the last N cycles in the newest cycle's
// vehicle frame, older cycles moved with the integrated Doppler ego-velocity and their point
// covariances grown by that motion's uncertainty, so the NDT of eq. (1)-(2) trusts old points less.

#include <deque>

#include <Eigen/Core>
#include <pcl/point_cloud.h>

#include "radar_ndt/point_types.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

class ProbabilisticSubmap {
 public:
  explicit ProbabilisticSubmap(std::size_t size = 3);

  /// Number of cycles kept (N ≥ 1). Shrinking drops the oldest.
  void setSize(std::size_t n);
  std::size_t getSize() const { return size_; }

  /// Adds a cycle (points in the vehicle frame at its time, with covariances) that came `dt`
  /// seconds after the previous one, when the vehicle moved with `ego_velocity` = (vx, vy, ω)
  /// (covariance `covariance`). Older cycles move by the inverse of exp(v̄·dt), v̄ the mean of the
  /// previous and this velocity (trapezoid rule; its covariance the mean of the two, halved); each
  /// point's covariance becomes R Σ Rᵀ + G Σ_m Gᵀ, with Σ_m = J Σ_v̄ Jᵀ dt² the motion's
  /// covariance and G = ∂p'/∂(motion).
  void add(const pcl::PointCloud<PointRadar>& cycle, const Eigen::Vector3d& ego_velocity,
           const Eigen::Matrix3d& covariance, double dt);

  /// All kept cycles in the newest cycle's frame, oldest first.
  pcl::PointCloud<PointRadar>::Ptr cloud() const;
  std::size_t cycles() const { return clouds_.size(); }
  /// The newest cycle as kept (its points' fields may be changed, e.g. weights; not its size).
  /// Requires cycles() > 0.
  pcl::PointCloud<PointRadar>& newest() { return clouds_.back(); }
  void clear();

  /// The motion used by the last add(): the newest frame in the previous one, and its covariance.
  const Pose2& lastMotion() const { return last_motion_; }
  const Eigen::Matrix3d& lastMotionCovariance() const { return last_motion_cov_; }

 private:
  std::size_t size_;
  std::deque<pcl::PointCloud<PointRadar>> clouds_;
  Eigen::Vector3d prev_velocity_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d prev_covariance_ = Eigen::Matrix3d::Zero();
  Pose2 last_motion_ = Pose2::Zero();
  Eigen::Matrix3d last_motion_cov_ = Eigen::Matrix3d::Zero();
};

/// Moves `cloud` (points in frame A) into frame B, where `motion` is B's pose in A and
/// `motion_cov` its covariance, growing each point's covariance as ProbabilisticSubmap does.
void transformWithUncertainty(pcl::PointCloud<PointRadar>& cloud, const Pose2& motion,
                              const Eigen::Matrix3d& motion_cov);

/// The clouds of `cycles` in one cloud, in order (width = size, height 1).
pcl::PointCloud<PointRadar>::Ptr concatenateCycles(const std::deque<pcl::PointCloud<PointRadar>>& cycles);

/// Covariance of integrateVelocity(v, dt) given Cov(v): J Σ_v Jᵀ dt², J = [V(θ) 0; 0 1].
Eigen::Matrix3d motionCovariance(const Eigen::Vector3d& v, const Eigen::Matrix3d& velocity_cov, double dt);

}  // namespace radar_ndt
