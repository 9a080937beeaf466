// The simulator's trajectory: poses with stamps, interpolated in time and by arc length, and the
// built-in city drive.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "radar_ndt/sim/radar_sim.h"

namespace radar_ndt {
namespace sim {

// ---- trajectory -------------------------------------------------------------------------------

SimTrajectory::SimTrajectory(const Trajectory& trajectory, double period) {
  if (trajectory.empty()) throw std::invalid_argument("radar_sim: the trajectory is empty");
  std::vector<double> stamps;
  std::vector<Pose2> poses;
  for (std::size_t k = 0; k < trajectory.size(); ++k) {
    stamps.push_back(trajectory.hasStamps() ? trajectory.stamps[k] - trajectory.stamps[0] : period * k);
    poses.push_back(toPose2(trajectory.poses[k]));
  }
  *this = SimTrajectory(std::move(stamps), std::move(poses));
}

SimTrajectory::SimTrajectory(std::vector<double> stamps, std::vector<Pose2> poses)
    : stamps_(std::move(stamps)), poses_(std::move(poses)) {
  if (poses_.size() < 2 || stamps_.size() != poses_.size())
    throw std::invalid_argument("radar_sim: a trajectory needs at least 2 poses with one stamp each");
  for (std::size_t k = 1; k < stamps_.size(); ++k)
    if (!(stamps_[k] > stamps_[k - 1])) throw std::invalid_argument("radar_sim: trajectory stamps must increase");
  arc_.assign(poses_.size(), 0.0);
  for (std::size_t k = 1; k < poses_.size(); ++k)
    arc_[k] = arc_[k - 1] + (poses_[k].head<2>() - poses_[k - 1].head<2>()).norm();
  // Direction of travel at each end: the nearest segment that moves (else the pose's heading).
  auto direction = [&](std::size_t j) {
    return std::atan2(poses_[j + 1].y() - poses_[j].y(), poses_[j + 1].x() - poses_[j].x());
  };
  start_heading_ = poses_.front().z();
  end_heading_ = poses_.back().z();
  for (std::size_t j = 0; j + 1 < poses_.size(); ++j)
    if (arc_[j + 1] - arc_[j] > 0.05) {
      start_heading_ = direction(j);
      break;
    }
  for (std::size_t j = poses_.size() - 1; j > 0; --j)
    if (arc_[j] - arc_[j - 1] > 0.05) {
      end_heading_ = direction(j - 1);
      break;
    }
}

std::size_t SimTrajectory::segment(double t) const {
  const auto it = std::upper_bound(stamps_.begin(), stamps_.end(), t);
  std::size_t k = static_cast<std::size_t>(it - stamps_.begin());
  k = k == 0 ? 0 : k - 1;
  return std::min(k, stamps_.size() - 2);
}

Pose2 SimTrajectory::at(double t) const {
  t = std::min(std::max(t, stamps_.front()), stamps_.back());
  const std::size_t k = segment(t);
  return interpolate(poses_[k], poses_[k + 1], (t - stamps_[k]) / (stamps_[k + 1] - stamps_[k]));
}

Eigen::Vector3d SimTrajectory::velocity(double t) const {
  const std::size_t k = segment(std::min(std::max(t, stamps_.front()), stamps_.back()));
  const double dt = stamps_[k + 1] - stamps_[k];
  const Pose2 d = between(poses_[k], poses_[k + 1]);
  const Pose2 here = at(t);
  // The segment's displacement expressed in the frame at t (a small correction for the heading
  // turned so far within the segment).
  const double dyaw = normalizeAngle(here.z() - poses_[k].z());
  const double c = std::cos(dyaw), s = std::sin(dyaw);
  return Eigen::Vector3d((c * d.x() + s * d.y()) / dt, (-s * d.x() + c * d.y()) / dt, d.z() / dt);
}

double SimTrajectory::arcAt(double t) const {
  t = std::min(std::max(t, stamps_.front()), stamps_.back());
  const std::size_t k = segment(t);
  const double u = (t - stamps_[k]) / (stamps_[k + 1] - stamps_[k]);
  return arc_[k] + u * (arc_[k + 1] - arc_[k]);
}

Pose2 SimTrajectory::atArc(double s) const {
  // Beyond the ends: straight on along the first / last direction of travel (the world is
  // generated a little past both ends of the path).
  const double extra = s < 0.0 ? s : (s > arc_.back() ? s - arc_.back() : 0.0);
  s = std::min(std::max(s, 0.0), arc_.back());
  auto it = std::upper_bound(arc_.begin(), arc_.end(), s);
  std::size_t k = static_cast<std::size_t>(it - arc_.begin());
  k = std::min(k == 0 ? 0 : k - 1, arc_.size() - 2);
  // Standstill segments (zero length) are skipped for the heading: it follows the direction of travel.
  const double len = arc_[k + 1] - arc_[k];
  const double u = len > 1e-9 ? (s - arc_[k]) / len : 0.0;
  const Pose2& a = poses_[k];
  const Pose2& b = poses_[k + 1];
  double heading = len > 0.05 ? std::atan2(b.y() - a.y(), b.x() - a.x()) : a.z();
  if (extra != 0.0) {
    const Pose2& end = extra < 0.0 ? poses_.front() : poses_.back();
    const double h = extra < 0.0 ? start_heading_ : end_heading_;
    return Pose2(end.x() + extra * std::cos(h), end.y() + extra * std::sin(h), h);
  }
  return Pose2(a.x() + u * (b.x() - a.x()), a.y() + u * (b.y() - a.y()), heading);
}

SimTrajectory builtinDrive(double duration, double period) {
  if (!(duration > period) || !(period > 0))
    throw std::invalid_argument("radar_sim: the built-in drive needs duration > period > 0");
  // A repeating 60 s pattern of (seconds, target speed m/s, yaw rate rad/s).
  struct Phase {
    double seconds, speed, yaw_rate;
  };
  static const Phase kPattern[] = {{6, 8, 0},         {14, 12, 0},   {7, 6, kPi / 14}, {12, 11, 0},
                                   {6, 5, -kPi / 12}, {5, 10, 0.04}, {4, 0, 0},        {6, 9, 0}};
  double pattern_length = 0;
  for (const Phase& p : kPattern) pattern_length += p.seconds;
  constexpr double kStep = 0.01, kAccel = 2.0;
  std::vector<double> stamps;
  std::vector<Pose2> poses;
  Pose2 pose(0, 0, 0);
  double v = 0, next = 0;
  for (double t = 0; t <= duration + 1e-9; t += kStep) {
    if (t + 1e-9 >= next) {
      stamps.push_back(next);
      poses.push_back(pose);
      next += period;
    }
    double u = std::fmod(t, pattern_length);
    const Phase* phase = &kPattern[0];
    for (const Phase& p : kPattern) {
      phase = &p;
      if (u < p.seconds) break;
      u -= p.seconds;
    }
    v += std::max(-kAccel * kStep, std::min(kAccel * kStep, phase->speed - v));
    const double w = phase->speed > 0 ? phase->yaw_rate * v / phase->speed : 0.0;
    pose.x() += v * std::cos(pose.z()) * kStep;
    pose.y() += v * std::sin(pose.z()) * kStep;
    pose.z() = normalizeAngle(pose.z() + w * kStep);
  }
  return SimTrajectory(std::move(stamps), std::move(poses));
}

}  // namespace sim
}  // namespace radar_ndt
