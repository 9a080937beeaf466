#include "radar_ndt/frontend/probabilistic_submap.h"

#include <cmath>

namespace radar_ndt {

ProbabilisticSubmap::ProbabilisticSubmap(std::size_t size) : size_(std::max<std::size_t>(1, size)) {}

void ProbabilisticSubmap::setSize(std::size_t n) {
  size_ = std::max<std::size_t>(1, n);
  while (clouds_.size() > size_) clouds_.pop_front();
}

void ProbabilisticSubmap::clear() {
  clouds_.clear();
  last_motion_.setZero();
  last_motion_cov_.setZero();
}

Eigen::Matrix3d motionCovariance(const Eigen::Vector3d& v, const Eigen::Matrix3d& velocity_cov, double dt) {
  const double th = v.z() * dt;
  double a = 1.0, b = 0.0;
  if (std::abs(th) > 1e-6) {
    a = std::sin(th) / th;
    b = (1.0 - std::cos(th)) / th;
  }
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  J.topLeftCorner<2, 2>() << a, -b, b, a;
  return J * velocity_cov * J.transpose() * (dt * dt);
}

void transformWithUncertainty(pcl::PointCloud<PointRadar>& cloud, const Pose2& motion,
                              const Eigen::Matrix3d& motion_cov) {
  const double c = std::cos(motion.z()), s = std::sin(motion.z());
  Eigen::Matrix2d Rt;  // R(−θ)
  Rt << c, s, -s, c;
  for (auto& p : cloud) {
    const Eigen::Vector2d d(p.x - motion.x(), p.y - motion.y());
    const Eigen::Vector2d q = Rt * d;
    // p' = R(−θ)(p − t): ∂p'/∂t = −R(−θ), ∂p'/∂θ = [[−s, c], [−c, −s]] (p − t).
    Eigen::Matrix<double, 2, 3> G;
    G.leftCols<2>() = -Rt;
    G.col(2) << -s * d.x() + c * d.y(), -c * d.x() - s * d.y();
    Eigen::Matrix2d C;
    C << p.cov_xx, p.cov_xy, p.cov_xy, p.cov_yy;
    C = Rt * C * Rt.transpose() + G * motion_cov * G.transpose();
    p.x = static_cast<float>(q.x());
    p.y = static_cast<float>(q.y());
    p.cov_xx = static_cast<float>(C(0, 0));
    p.cov_xy = static_cast<float>(C(0, 1));
    p.cov_yy = static_cast<float>(C(1, 1));
  }
}

void ProbabilisticSubmap::add(const pcl::PointCloud<PointRadar>& cycle, const Eigen::Vector3d& v,
                              const Eigen::Matrix3d& cov, double dt) {
  if (clouds_.empty()) {
    last_motion_.setZero();
    last_motion_cov_.setZero();
  } else {
    const Eigen::Vector3d v_mean = 0.5 * (prev_velocity_ + v);
    const Eigen::Matrix3d cov_mean = 0.25 * (prev_covariance_ + cov);
    last_motion_ = integrateVelocity(v_mean, dt);
    last_motion_cov_ = motionCovariance(v_mean, cov_mean, dt);
    // Only the cycles that stay are moved (N = 1 keeps none).
    while (clouds_.size() >= size_) clouds_.pop_front();
    for (auto& old : clouds_) transformWithUncertainty(old, last_motion_, last_motion_cov_);
  }
  clouds_.push_back(cycle);
  while (clouds_.size() > size_) clouds_.pop_front();
  prev_velocity_ = v;
  prev_covariance_ = cov;
}

pcl::PointCloud<PointRadar>::Ptr concatenateCycles(const std::deque<pcl::PointCloud<PointRadar>>& cycles) {
  pcl::PointCloud<PointRadar>::Ptr out(new pcl::PointCloud<PointRadar>);
  std::size_t n = 0;
  for (const auto& c : cycles) n += c.size();
  out->reserve(n);
  for (const auto& c : cycles) out->insert(out->end(), c.begin(), c.end());
  out->width = static_cast<std::uint32_t>(out->size());
  out->height = 1;
  return out;
}

pcl::PointCloud<PointRadar>::Ptr ProbabilisticSubmap::cloud() const {
  return concatenateCycles(clouds_);
}

}  // namespace radar_ndt
