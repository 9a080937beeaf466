#include "radar_ndt/evaluation/metrics_6dof.h"

#include <algorithm>
#include <cmath>

#include <Eigen/SVD>

#include "radar_ndt/statistics.h"

namespace radar_ndt {
namespace {

constexpr double kDegreesPerRadian = 180.0 / kPi;

/// rpg get_best_yaw: θ maximising trace(Rz(θ) C).
double bestYaw(const Eigen::Matrix3d& C) {
  const double A = C(0, 1) - C(1, 0), B = C(0, 0) + C(1, 1);
  return kPi / 2 - std::atan2(B, A);
}

/// rpg transformations.euler_from_matrix(R, 'rzyx'): (yaw, pitch, roll) with R = Rz(yaw) Ry(pitch)
/// Rx(roll).
Eigen::Vector3d eulerZyx(const Eigen::Matrix3d& M) {
  const double cy = std::sqrt(M(0, 0) * M(0, 0) + M(1, 0) * M(1, 0));
  constexpr double kEps = 8.8817841970012523e-16;  // numpy.finfo(float).eps * 4.0
  if (cy > kEps) return {std::atan2(M(1, 0), M(0, 0)), std::atan2(-M(2, 0), cy), std::atan2(M(2, 1), M(2, 2))};
  return {0.0, std::atan2(-M(2, 0), cy), std::atan2(-M(1, 2), M(1, 1))};
}

double rmsOf(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s / static_cast<double>(v.size()));
}
double meanOf(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

/// rpg compute_comparison_indices_length for pose i: the j >= i whose path length is nearest to
/// `target`, strictly within `max_difference`, the first on ties; −1 for none. rpg scans every j;
/// the path length never decreases, so the nearest is the first at or past `target` or the first
/// of the value just before it: two binary searches instead of a pass over the rest.
std::ptrdiff_t comparisonIndex(const std::vector<double>& dist, std::size_t i, double target, double max_difference) {
  const auto from = dist.begin() + static_cast<std::ptrdiff_t>(i);
  const auto at = std::lower_bound(from, dist.end(), target);
  std::ptrdiff_t best = -1;
  double error = max_difference;
  if (at != from) {  // the value just before target, at its first index (the first on ties)
    const auto before = std::lower_bound(from, at, *(at - 1));
    const double d = std::abs(*before - target);
    if (d < error) best = before - dist.begin(), error = d;
  }
  if (at != dist.end() && std::abs(*at - target) < error) best = at - dist.begin();
  return best;
}

}  // namespace

bool isPlanar(const std::vector<Eigen::Isometry3d>& poses, double tol) {
  for (const auto& T : poses) {
    const Eigen::Matrix3d& R = T.linear();
    if (std::abs(T.translation().z()) > tol || std::abs(R(2, 0)) > tol || std::abs(R(2, 1)) > tol ||
        std::abs(R(0, 2)) > tol || std::abs(R(1, 2)) > tol)
      return false;
  }
  return true;
}

bool isPlanar(const PosePairs& pairs, double tol) {
  return isPlanar(pairs.gt, tol) && isPlanar(pairs.est, tol);
}

Eigen::Isometry3d alignTrajectory(const PosePairs& pairs, TrajectoryAlignment alignment) {
  const std::size_t n = pairs.size();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (n == 0) return T;
  Eigen::Vector3d mu_m = Eigen::Vector3d::Zero(), mu_d = Eigen::Vector3d::Zero();  // model = gt, data = est
  for (std::size_t i = 0; i < n; ++i) {
    mu_m += pairs.gt[i].translation();
    mu_d += pairs.est[i].translation();
  }
  mu_m /= static_cast<double>(n);
  mu_d /= static_cast<double>(n);
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();  // 1/n Σ m dᵀ, centred
  for (std::size_t i = 0; i < n; ++i)
    C += (pairs.gt[i].translation() - mu_m) * (pairs.est[i].translation() - mu_d).transpose();
  C /= static_cast<double>(n);
  Eigen::Matrix3d R;
  if (alignment == TrajectoryAlignment::PositionYaw) {
    // rpg: rot_C = data_zcᵀ model_zc = n Cᵀ; the 1/n does not move the maximum.
    R = Eigen::AngleAxisd(bestYaw(C.transpose()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  } else {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(C, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
    if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) S(2, 2) = -1;
    R = svd.matrixU() * S * svd.matrixV().transpose();
  }
  T.linear() = R;
  T.translation() = mu_m - R * mu_d;
  return T;
}

AbsoluteError6Dof absoluteTrajectoryError6Dof(const PosePairs& pairs, TrajectoryAlignment alignment) {
  AbsoluteError6Dof out;
  out.poses = pairs.size();
  if (pairs.size() == 0) return out;
  out.alignment = alignTrajectory(pairs, alignment);
  double sq_t = 0, sq_r = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Eigen::Isometry3d e = out.alignment * pairs.est[i];
    sq_t += (pairs.gt[i].translation() - e.translation()).squaredNorm();
    // rpg: e_R = R_we R_wgᵀ, its angle as the norm of logmap_so3.
    const double angle = Eigen::AngleAxisd(e.linear() * pairs.gt[i].linear().transpose()).angle() * kDegreesPerRadian;
    sq_r += angle * angle;
  }
  out.rmse_m = std::sqrt(sq_t / static_cast<double>(pairs.size()));
  out.rot_rmse_deg = std::sqrt(sq_r / static_cast<double>(pairs.size()));
  return out;
}

RelativeError relativeError(const PosePairs& pairs, double distance, double max_difference) {
  RelativeError out;
  out.distance = distance;
  if (!(distance > 0)) throw std::invalid_argument("relativeError: the distance must be positive");
  if (max_difference < 0) max_difference = 0.2 * distance;
  const std::vector<double> dist = pathDistances(pairs.gt);
  std::vector<double> trans, yaw, gravity, rot;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const std::ptrdiff_t best = comparisonIndex(dist, i, dist[i] + distance, max_difference);
    if (best < 0) continue;
    const std::size_t j = static_cast<std::size_t>(best);
    const Eigen::Isometry3d est_ij = pairs.est[i].inverse() * pairs.est[j];
    const Eigen::Isometry3d gt_ij = pairs.gt[i].inverse() * pairs.gt[j];
    const Eigen::Isometry3d e_c2 = gt_ij.inverse() * est_ij;
    Eigen::Isometry3d R2 = Eigen::Isometry3d::Identity();
    R2.linear() = pairs.est[j].linear();
    const Eigen::Isometry3d e_w = R2 * e_c2 * R2.inverse();
    trans.push_back(e_w.translation().norm());
    const Eigen::Vector3d ypr = eulerZyx(e_w.linear());
    yaw.push_back(std::abs(ypr.x()) * kDegreesPerRadian);
    gravity.push_back(std::sqrt(ypr.y() * ypr.y() + ypr.z() * ypr.z()) * kDegreesPerRadian);
    rot.push_back(rotationAngle(e_w.linear()) * kDegreesPerRadian);
  }
  out.samples = trans.size();
  if (out.samples < 2) return out;  // rpg: "Too few samples! Will not compute."
  out.trans_mean_m = meanOf(trans);
  out.trans_median_m = median(trans);
  out.trans_rmse_m = rmsOf(trans);
  out.trans_mean_pct = 100.0 * out.trans_mean_m / distance;
  out.yaw_mean_deg = meanOf(yaw);
  out.gravity_mean_deg = meanOf(gravity);
  out.rot_mean_deg = meanOf(rot);
  return out;
}

FinalError finalPositionError(const PosePairs& pairs) {
  FinalError out;
  if (pairs.size() < 2) return out;
  // rpg alignPositionYawSingle: R = Rz(best yaw of R_est,0 R_gt,0ᵀ), t = p_gt,0 − R p_est,0.
  const Eigen::Matrix3d C = pairs.est[0].linear() * pairs.gt[0].linear().transpose();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(bestYaw(C), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d t = pairs.gt[0].translation() - R * pairs.est[0].translation();
  const std::vector<double> dist = pathDistances(pairs.gt);
  out.distance_m = dist.back();
  out.final_m = (R * pairs.est.back().translation() + t - pairs.gt.back().translation()).norm();
  if (out.distance_m > 0) out.final_pct = 100.0 * out.final_m / out.distance_m;
  return out;
}

double loopClosureErrorPct(const std::vector<Eigen::Isometry3d>& poses) {
  if (poses.size() < 2) return kUndefinedError;
  const double length = pathDistances(poses).back();
  if (!(length > 0)) return kUndefinedError;
  return 100.0 * (poses.back().translation() - poses.front().translation()).norm() / length;
}

}  // namespace radar_ndt
