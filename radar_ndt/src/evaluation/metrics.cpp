#include "radar_ndt/evaluation/metrics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace radar_ndt {
namespace {

constexpr double kRadToDeg = 180.0 / kPi;

/// E = (est_i⁻¹ est_j)⁻¹ (gt_i⁻¹ gt_j)
Eigen::Isometry3d relativeError(const PosePairs& p, std::size_t i, std::size_t j) {
  const Eigen::Isometry3d d_gt = p.gt[i].inverse() * p.gt[j];
  const Eigen::Isometry3d d_est = p.est[i].inverse() * p.est[j];
  return d_est.inverse() * d_gt;
}

}  // namespace

double rotationAngle(const Eigen::Matrix3d& R) {
  const double d = 0.5 * (R.trace() - 1.0);
  return std::acos(std::max(-1.0, std::min(1.0, d)));
}

std::vector<double> pathDistances(const std::vector<Eigen::Isometry3d>& poses) {
  std::vector<double> dist(poses.size(), 0.0);
  for (std::size_t i = 1; i < poses.size(); ++i)
    dist[i] = dist[i - 1] + (poses[i].translation() - poses[i - 1].translation()).norm();
  return dist;
}

PosePairs associate(const Trajectory& gt, const Trajectory& est) {
  PosePairs p;
  if (!gt.hasStamps() || !est.hasStamps()) {
    if (gt.size() != est.size())
      throw std::invalid_argument("ground truth has " + std::to_string(gt.size()) + " poses and the estimate " +
                                  std::to_string(est.size()) +
                                  ": association by index (a trajectory without timestamps) needs equal lengths");
    p.gt = gt.poses;
    p.est = est.poses;
  } else {
    for (std::size_t i = 0; i < est.size(); ++i) {
      const double t = est.stamps[i];
      Eigen::Isometry3d g;
      if (!gt.poseAt(t, &g)) continue;  // outside the ground truth's span
      p.gt.push_back(g);
      p.est.push_back(est.poses[i]);
      p.stamps.push_back(t);
    }
  }
  if (p.size() < 2)
    throw std::invalid_argument("fewer than 2 estimated poses could be associated with the ground truth" +
                                std::string(gt.hasStamps() && est.hasStamps() ? " (no overlap in time?)" : ""));
  return p;
}

SegmentError kittiError(const PosePairs& pairs, const std::vector<double>& lengths, std::size_t step) {
  if (step == 0) throw std::invalid_argument("kittiError: step must be at least 1");
  const std::vector<double> dist = pathDistances(pairs.gt);
  SegmentError out;
  double sum_t = 0, sum_r = 0;
  for (double L : lengths) {
    SegmentError::PerLength pl;
    pl.length = L;
    double lt = 0, lr = 0;
    for (std::size_t first = 0; first < pairs.size(); first += step) {
      // the first frame whose path length from `first` exceeds L
      const auto it = std::upper_bound(dist.begin() + static_cast<std::ptrdiff_t>(first), dist.end(), dist[first] + L);
      if (it == dist.end()) continue;  // runs past the end of the sequence (and so will later firsts)
      const std::size_t last = static_cast<std::size_t>(it - dist.begin());
      const Eigen::Isometry3d E = relativeError(pairs, first, last);
      lt += E.translation().norm() / L;
      lr += rotationAngle(E.linear()) / L;
      ++pl.segments;
    }
    if (pl.segments > 0) {
      pl.trans_err_pct = 100.0 * lt / static_cast<double>(pl.segments);
      pl.rot_err_deg_per_m = kRadToDeg * lr / static_cast<double>(pl.segments);
    }
    sum_t += lt;
    sum_r += lr;
    out.segments += pl.segments;
    out.per_length.push_back(pl);
  }
  if (out.segments > 0) {
    out.trans_err_pct = 100.0 * sum_t / static_cast<double>(out.segments);
    out.rot_err_deg_per_m = kRadToDeg * sum_r / static_cast<double>(out.segments);
  }
  return out;
}

SegmentError oneMeterError(const PosePairs& pairs, double length) {
  if (!(length > 0)) throw std::invalid_argument("oneMeterError: length must be positive");
  const std::vector<double> dist = pathDistances(pairs.gt);
  SegmentError out;
  SegmentError::PerLength pl;
  pl.length = length;
  double st = 0, sr = 0;
  for (std::size_t first = 0; first < pairs.size(); ++first) {
    // the first pose whose path length from `first` reaches `length`
    const auto it =
        std::lower_bound(dist.begin() + static_cast<std::ptrdiff_t>(first), dist.end(), dist[first] + length);
    if (it == dist.end()) break;
    const std::size_t last = static_cast<std::size_t>(it - dist.begin());
    const double actual = dist[last] - dist[first];
    const Eigen::Isometry3d E = relativeError(pairs, first, last);
    st += E.translation().norm() / actual;
    sr += rotationAngle(E.linear()) / actual;
    ++pl.segments;
  }
  if (pl.segments > 0) {
    pl.trans_err_pct = 100.0 * st / static_cast<double>(pl.segments);
    pl.rot_err_deg_per_m = kRadToDeg * sr / static_cast<double>(pl.segments);
  }
  out.trans_err_pct = pl.trans_err_pct;
  out.rot_err_deg_per_m = pl.rot_err_deg_per_m;
  out.segments = pl.segments;
  out.per_length.push_back(pl);
  return out;
}

FrameError frameError(const PosePairs& pairs, std::size_t step) {
  if (step == 0) throw std::invalid_argument("frameError: step must be at least 1");
  FrameError out;
  double st = 0, sr = 0;
  for (std::size_t i = 0; i + step < pairs.size(); i += step) {
    const Eigen::Isometry3d E = relativeError(pairs, i, i + step);
    st += E.translation().norm();
    sr += rotationAngle(E.linear());
    ++out.pairs;
  }
  if (out.pairs > 0) {
    out.trans_err_m = st / static_cast<double>(out.pairs);
    out.rot_err_deg = kRadToDeg * sr / static_cast<double>(out.pairs);
  }
  return out;
}

AbsoluteError absoluteTrajectoryError(const PosePairs& pairs) {
  AbsoluteError out;
  const std::size_t n = pairs.size();
  out.poses = n;
  if (n == 0) return out;
  Eigen::Vector2d mg = Eigen::Vector2d::Zero(), me = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    mg += pairs.gt[i].translation().head<2>();
    me += pairs.est[i].translation().head<2>();
  }
  mg /= static_cast<double>(n);
  me /= static_cast<double>(n);
  // Least-squares rotation in 2D (Umeyama without scale): θ = atan2(Σ e × g, Σ e · g) on centred points.
  double s_cross = 0, s_dot = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d e = pairs.est[i].translation().head<2>() - me;
    const Eigen::Vector2d g = pairs.gt[i].translation().head<2>() - mg;
    s_cross += e.x() * g.y() - e.y() * g.x();
    s_dot += e.dot(g);
  }
  const double theta = std::atan2(s_cross, s_dot);
  const Eigen::Rotation2Dd R(theta);
  const Eigen::Vector2d t = mg - R * me;
  double sq = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d r = R * pairs.est[i].translation().head<2>() + t - pairs.gt[i].translation().head<2>();
    sq += r.squaredNorm();
  }
  out.rmse_m = std::sqrt(sq / static_cast<double>(n));
  out.alignment = Pose2(t.x(), t.y(), theta);
  return out;
}

}  // namespace radar_ndt
