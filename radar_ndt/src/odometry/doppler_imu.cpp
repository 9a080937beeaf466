#include "radar_ndt/odometry/doppler_imu.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "radar_ndt/frontend/ego_velocity_3d.h"
#include "radar_ndt/odometry/imu_velocity.h"
#include "radar_ndt/odometry/inertial_filter.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/se3.h"

namespace radar_ndt {

namespace {

std::string format(const char* fmt, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

/// Sorted by time, non-finite messages and repeated or earlier times dropped (said once, counted);
/// gaps longer than `max_gap` said once with their count and the longest.
std::vector<ImuSample> cleanImu(std::vector<ImuSample> imu, double max_gap, std::vector<std::string>& problems) {
  const bool ordered =
      std::is_sorted(imu.begin(), imu.end(), [](const ImuSample& a, const ImuSample& b) { return a.t < b.t; });
  std::stable_sort(imu.begin(), imu.end(), [](const ImuSample& a, const ImuSample& b) { return a.t < b.t; });
  std::vector<ImuSample> out;
  out.reserve(imu.size());
  std::size_t dropped = 0, gaps = 0;
  double longest = 0;
  for (const ImuSample& s : imu) {
    if (!std::isfinite(s.t) || !s.gyro.allFinite() || !s.accel.allFinite() || (!out.empty() && s.t <= out.back().t)) {
      ++dropped;
      continue;
    }
    if (!out.empty() && s.t - out.back().t > max_gap) {
      ++gaps;
      longest = std::max(longest, s.t - out.back().t);
    }
    out.push_back(s);
  }
  if (!ordered) problems.push_back("the IMU messages were not in time order: sorted by their stamps");
  if (dropped)
    problems.push_back(format("%.0f IMU messages not finite or at a time already seen: dropped", double(dropped)));
  if (gaps)
    problems.push_back(
        format("%.0f gaps in the IMU longer than %.3f s (the longest %.3f s): the gyro is held across them",
               double(gaps), max_gap, longest));
  return out;
}

/// The body velocity at a time: linear between the valid samples around it, held beyond the ends;
/// and its rate of change there (the slope of that line, zero beyond the ends). Asked at
/// increasing times.
class VelocityTrack {
 public:
  explicit VelocityTrack(std::vector<BodyVelocitySample> valid) : valid_(std::move(valid)) {}
  Eigen::Vector3d operator()(double t, Eigen::Vector3d* slope) {
    while (cursor_ + 1 < valid_.size() && valid_[cursor_ + 1].t <= t) ++cursor_;
    slope->setZero();
    if (t <= valid_[cursor_].t || cursor_ + 1 == valid_.size()) return valid_[cursor_].velocity;
    const BodyVelocitySample &a = valid_[cursor_], &b = valid_[cursor_ + 1];
    const double u = (t - a.t) / (b.t - a.t);
    *slope = (b.velocity - a.velocity) / (b.t - a.t);
    return (1 - u) * a.velocity + u * b.velocity;
  }

 private:
  std::vector<BodyVelocitySample> valid_;
  std::size_t cursor_ = 0;
};

/// R turned a fraction `gain` of the way that brings the measured up (the specific force `f`,
/// body axes) onto the world's z, about the horizontal axis between them: roll and pitch only.
Eigen::Matrix3d pullToGravity(const Eigen::Matrix3d& R, const Eigen::Vector3d& f, double gain) {
  const Eigen::Vector3d up = R * f.normalized();
  const Eigen::Vector3d axis = up.cross(Eigen::Vector3d::UnitZ());
  const double s = axis.norm();
  if (s < 1e-12) return R;
  return expSO3(axis / s * std::asin(std::min(s, 1.0)) * gain) * R;
}

/// The baseline's loop: the gyro integrated from `R`, roll and pitch pulled to gravity, the valid
/// velocities (interpolated between them) turned into the world and integrated; a pose for every
/// sample in the IMU's span into `result`.
void integrate(const std::vector<ImuSample>& imu, const std::vector<BodyVelocitySample>& velocities, Eigen::Matrix3d R,
               const DopplerImuOptions& o, DopplerImuResult& result) {
  std::vector<BodyVelocitySample> valid;
  for (const auto& v : velocities)
    if (v.valid && std::isfinite(v.t) && v.velocity.allFinite() && (valid.empty() || v.t > valid.back().t))
      valid.push_back(v);
  if (valid.empty()) throw std::invalid_argument("doppler-imu: no valid Doppler velocity");
  result.trajectory = Trajectory();
  result.held_velocities = 0;
  VelocityTrack velocityAt(std::move(valid));
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  std::size_t next = 0;  // the next velocity sample to write a pose for
  while (next < velocities.size() && velocities[next].t < imu.front().t) ++next;
  const double gain_per_s = 1.0 / o.attitude_time_constant;
  for (std::size_t k = 1; k < imu.size() && next < velocities.size(); ++k) {
    const double t0 = imu[k - 1].t, t1 = imu[k].t, dt = t1 - t0;
    const Eigen::Matrix3d R0 = R;
    const Eigen::Vector3d p0 = p;
    const Eigen::Vector3d omega = 0.5 * (imu[k - 1].gyro + imu[k].gyro) - result.gyro_bias;
    R = R * expSO3(omega * dt);
    Eigen::Vector3d dv;
    const Eigen::Vector3d v = velocityAt(0.5 * (t0 + t1), &dv);
    // The accelerometer less the body's own acceleration as the Doppler velocity and the gyro give
    // it (a_b = dv/dt + ω × v: a turn's centripetal term above all), so that what is left is
    // gravity; it pulls roll and pitch only when that is about 1 g.
    const Eigen::Vector3d f = imu[k].accel - (dv + omega.cross(v));
    if (std::abs(f.norm() - o.gravity) < o.still_tolerance) R = pullToGravity(R, f, std::min(1.0, gain_per_s * dt));
    const Eigen::Quaterniond q0(R0), q1(R);
    p += Eigen::Quaterniond(q0.slerp(0.5, q1)).toRotationMatrix() * v * dt;
    for (; next < velocities.size() && velocities[next].t <= t1; ++next) {
      const double u = (velocities[next].t - t0) / dt;
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = q0.slerp(u, q1).toRotationMatrix();
      pose.translation() = p0 + u * (p - p0);
      if (!result.trajectory.stamps.empty() && velocities[next].t <= result.trajectory.stamps.back()) continue;
      result.trajectory.stamps.push_back(velocities[next].t);
      result.trajectory.poses.push_back(pose);
      result.held_velocities += !velocities[next].valid;
    }
  }
}

/// The last velocity the gate accepted: its time, its value and covariance, the body's attitude.
struct Accepted {
  double t = 0;
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d attitude = Eigen::Matrix3d::Identity();
};

/// Whether `v` lies within the gate of the IMU's prediction from `a` (EKF-RIO's Mahalanobis test:
/// the prediction's covariance and the sample's).
bool withinGate(const Accepted& a, const BodyVelocitySample& v, const std::vector<ImuSample>& imu,
                const Eigen::Vector3d& gyro_bias, const DopplerImuOptions& o) {
  const auto later = [](double t, const ImuSample& s) { return t < s.t; };
  const auto first = std::upper_bound(imu.begin(), imu.end(), a.t, later);
  ImuSample from = *(first == imu.begin() ? first : first - 1);  // the reading at a.t, held
  from.t = a.t;
  const Eigen::Vector3d predicted = predictBodyVelocity(a.attitude, a.velocity, from, first, imu.end(), v.t, gyro_bias,
                                                        Eigen::Vector3d::Zero(), o.gravity);
  const Eigen::Matrix3d S =
      predictedVelocityCovariance(a.covariance, v.t - a.t, o.velocity_gate_floor, o.velocity_gate_sigma) + v.covariance;
  const Eigen::Vector3d innovation = v.velocity - predicted;
  const double d2 = innovation.dot(S.ldlt().solve(innovation));
  return std::isfinite(d2) && d2 <= EgoVelocityPrior().gate;
}

/// Marks invalid every valid sample (time-ordered) beyond the gate of the prediction from the last
/// accepted one; the attitude at each time is the first pass's `poses`. The first accepted
/// velocity is zero at the IMU's first message after a still start, else the first valid sample.
/// Returns how many were refused.
std::size_t gateVelocities(std::vector<BodyVelocitySample>& velocities, const std::vector<ImuSample>& imu,
                           const Trajectory& poses, const StillStart& start, const DopplerImuOptions& o) {
  Accepted a;
  bool accepted = start.still;
  a.t = imu.front().t;
  a.attitude = start.attitude;
  std::size_t gated = 0;
  for (BodyVelocitySample& v : velocities) {
    Eigen::Isometry3d pose;
    if (!v.valid || !v.velocity.allFinite() || !(v.t > a.t) || v.t > imu.back().t || !poses.poseAt(v.t, &pose))
      continue;
    if (accepted && !withinGate(a, v, imu, start.gyro_bias, o)) {
      v.valid = false;
      ++gated;
      continue;
    }
    a = Accepted{v.t, v.velocity, v.covariance.allFinite() ? v.covariance : Eigen::Matrix3d::Zero(), pose.linear()};
    accepted = true;
  }
  return gated;
}

}  // namespace

void DopplerImuOptions::validate() const {
  checkFields(*this, "DopplerImuOptions");
}

DopplerImuResult runDopplerImu(std::vector<ImuSample> imu_in, std::vector<BodyVelocitySample> velocities,
                               const DopplerImuOptions& o) {
  o.validate();
  DopplerImuResult result;
  const std::vector<ImuSample> imu = cleanImu(std::move(imu_in), o.max_imu_gap, result.problems);
  if (imu.size() < 2) throw std::invalid_argument("doppler-imu: fewer than two usable IMU messages");
  // The scans' measurement times; the valid ones are what the velocity is interpolated from.
  for (auto& v : velocities) v.t -= o.radar_latency;
  std::stable_sort(velocities.begin(), velocities.end(),
                   [](const BodyVelocitySample& a, const BodyVelocitySample& b) { return a.t < b.t; });
  const StillStart start = readStillStart(imu, o.initial_seconds, o.gravity, result.problems);
  result.gyro_bias = start.gyro_bias;
  integrate(imu, velocities, start.attitude, o, result);
  if (!o.velocity_gate) return result;
  result.gated_velocities = gateVelocities(velocities, imu, result.trajectory, start, o);
  if (result.gated_velocities == 0) return result;
  result.problems.push_back(
      format("%.0f scans' Doppler velocity beyond the IMU's prediction (chi-square %.2f): held over as invalid ones "
             "(many: check radar_latency and the IMU's axes)",
             double(result.gated_velocities), EgoVelocityPrior().gate));
  integrate(imu, velocities, start.attitude, o, result);
  return result;
}

}  // namespace radar_ndt
