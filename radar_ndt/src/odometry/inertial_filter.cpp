#include "radar_ndt/odometry/inertial_filter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "radar_ndt/se2.h"
#include "radar_ndt/se3.h"

namespace radar_ndt {

namespace {

std::string figures(const char* fmt, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

}  // namespace

StillStart readStillStart(const std::vector<ImuSample>& imu, double seconds, double gravity,
                          std::vector<std::string>& problems) {
  if (imu.empty()) throw std::invalid_argument("no IMU message to start from");
  Eigen::Vector3d f0 = Eigen::Vector3d::Zero(), w0 = Eigen::Vector3d::Zero();
  std::size_t n0 = 0;
  double norm_min = 1e9, norm_max = 0;
  for (const ImuSample& s : imu) {
    if (s.t > imu.front().t + seconds && n0 > 0) break;
    f0 += s.accel;
    w0 += s.gyro;
    norm_min = std::min(norm_min, s.accel.norm());
    norm_max = std::max(norm_max, s.accel.norm());
    ++n0;
  }
  f0 /= double(n0);
  w0 /= double(n0);
  // An accelerometer whose gravity is not along the body's z: the IMU's axes are not what the
  // description says (the question rio's users ask most). The run goes on from what it reads.
  const double tilt = std::acos(std::clamp(f0.normalized().z(), -1.0, 1.0)) * 180.0 / kPi;
  if (tilt > 45.0)
    problems.push_back(
        figures("the accelerometer reads gravity along (%.2f, %.2f, %.2f) m/s^2 at the start, "
                "%.0f degrees from the body's z (up): check the IMU's axes and mounting",
                f0.x(), f0.y(), f0.z(), tilt));
  StillStart out;
  out.still = norm_max - norm_min < 0.1 * gravity && w0.norm() < 0.05;
  if (out.still)
    out.gyro_bias = w0;
  else
    problems.push_back(
        figures("the rig was not still in the first %.2f s (accelerometer %.2f to %.2f m/s^2): "
                "no gyro bias taken",
                seconds, norm_min, norm_max));
  out.attitude = Eigen::Quaterniond::FromTwoVectors(f0.normalized(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return out;
}

void InertialFilterOptions::validate() const {
  checkFields(*this, "InertialFilterOptions");
}

InertialFilter::InertialFilter(const InertialFilterOptions& o) : options_(o) {
  options_.validate();
}

void InertialFilter::initialize(const std::vector<ImuSample>& imu, std::vector<std::string>& problems) {
  const StillStart start = readStillStart(imu, options_.initial_seconds, options_.gravity, problems);
  R_ = start.attitude;
  gyro_bias_ = start.gyro_bias;
  p_.setZero();
  accel_bias_.setZero();
  P_.setZero();
  const double att = options_.initial_attitude_deg * kPi / 180;
  // Position and yaw are the odometry frame's own choice: known exactly at the start.
  P_.block<2, 2>(3, 3) = Eigen::Matrix2d::Identity() * att * att;
  const double bg = start.still ? options_.initial_gyro_bias : 10 * options_.initial_gyro_bias;
  P_.block<3, 3>(6, 6) = Eigen::Matrix3d::Identity() * bg * bg;
  P_.block<3, 3>(9, 9) = Eigen::Matrix3d::Identity() * options_.initial_accel_bias * options_.initial_accel_bias;
  still_start_ = start.still;
  initialized_ = true;
}

void InertialFilter::predict(const ImuSample& a, const ImuSample& b, const Eigen::Vector3d& velocity,
                             const Eigen::Matrix3d& velocity_covariance, double interval) {
  const double dt = b.t - a.t;
  if (!(dt > 0)) return;
  const Eigen::Vector3d omega = 0.5 * (a.gyro + b.gyro) - gyro_bias_;
  const Eigen::Matrix3d R0 = R_;
  R_ = R_ * expSO3(omega * dt);
  const Eigen::Quaterniond q0(R0), q1(R_);
  const Eigen::Matrix3d Rm = q0.slerp(0.5, q1).toRotationMatrix();
  const Eigen::Vector3d step = Rm * velocity * dt;
  p_ += step;
  // δp' = δp − [R v dt]× δθ; δθ' = δθ − R dt δb_g (R_true = Exp(δθ) R, ω_true = ω̂ − δb_g).
  Matrix12d F = Matrix12d::Identity();
  F.block<3, 3>(0, 3) = -skew(step);
  F.block<3, 3>(3, 6) = -Rm * dt;
  Matrix12d Q = Matrix12d::Zero();
  // The velocity's error holds over the whole scan interval: its share of dt adds up to
  // Σ_v interval² over the interval, a fully correlated error.
  Q.block<3, 3>(0, 0) = Rm * velocity_covariance * Rm.transpose() * dt * std::max(interval, dt);
  Q.block<3, 3>(3, 3).diagonal().setConstant(options_.gyro_noise * options_.gyro_noise * dt);
  Q.block<3, 3>(6, 6).diagonal().setConstant(options_.gyro_bias_walk * options_.gyro_bias_walk * dt);
  Q.block<3, 3>(9, 9).diagonal().setConstant(options_.accel_bias_walk * options_.accel_bias_walk * dt);
  P_ = F * P_ * F.transpose() + Q;
}

bool InertialFilter::updateGravity(const Eigen::Vector3d& specific_force, const Eigen::Vector3d& acceleration,
                                   const Eigen::Matrix3d& acceleration_covariance) {
  const Eigen::Vector3d g_body = specific_force - acceleration - accel_bias_;
  if (!g_body.allFinite() || std::abs(g_body.norm() - options_.gravity) > options_.still_tolerance) return false;
  const Eigen::Vector3d r = R_ * g_body - options_.gravity * Eigen::Vector3d::UnitZ();
  Eigen::Matrix<double, 3, 12> H = Eigen::Matrix<double, 3, 12>::Zero();
  H.block<3, 3>(0, 3) = options_.gravity * skew(Eigen::Vector3d::UnitZ());
  H.block<3, 3>(0, 9) = R_;
  const Eigen::Matrix3d noise = Eigen::Matrix3d::Identity() * options_.gravity_sigma * options_.gravity_sigma +
                                R_ * acceleration_covariance * R_.transpose();
  const Eigen::Matrix3d S = H * P_ * H.transpose() + noise;
  Eigen::Matrix<double, 12, 3> K = P_ * H.transpose() * S.inverse();
  // Gravity corrects roll, pitch and the accelerometer's bias only: what is left of the body's
  // acceleration in it must not leak into yaw, the position or the gyro's bias through their
  // correlations (a Schmidt update: those rows of the gain are held at zero).
  K.topRows<3>().setZero();
  K.row(5).setZero();
  K.middleRows<3>(6).setZero();
  correct(K * r);
  const Matrix12d IKH = Matrix12d::Identity() - K * H;
  P_ = IKH * P_ * IKH.transpose() + K * noise * K.transpose();
  return true;
}

bool InertialFilter::updatePose(const Eigen::Isometry3d& measured, const Matrix6d& covariance,
                                const std::array<bool, 6>& measured_axes, double* distance) {
  if (distance) *distance = std::numeric_limits<double>::quiet_NaN();
  if (!measured.matrix().allFinite() || !covariance.allFinite()) return false;
  Eigen::Matrix<double, 6, 1> r;
  r.head<3>() = measured.translation() - p_;
  r.tail<3>() = logSO3(measured.linear() * R_.transpose());
  Eigen::Matrix<double, 6, 12> H = Eigen::Matrix<double, 6, 12>::Zero();
  H.leftCols<6>().setIdentity();
  const Matrix6d S = P_.topLeftCorner<6, 6>() + covariance;
  const Eigen::LDLT<Matrix6d> ldlt(S);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
  const double d2 = r.dot(ldlt.solve(r));
  if (distance) *distance = d2;
  if (!(d2 <= options_.match_gate)) return false;
  Eigen::Matrix<double, 12, 6> K = P_ * H.transpose() * ldlt.solve(Matrix6d::Identity());
  // A Schmidt (consider) update: the match moves only the pose components it measures, not the
  // biases nor (through their correlations) the components it leaves to the IMU. Its errors are
  // correlated from scan to scan (each scan meets the same local map), which the filter cannot
  // know; let into the gyro's bias they integrate into yaw (docs/odometry_6dof.md).
  K.bottomRows<6>().setZero();
  for (int i = 0; i < 6; ++i)
    if (!measured_axes[static_cast<std::size_t>(i)]) K.row(i).setZero();
  correct(K * r);
  const Matrix12d IKH = Matrix12d::Identity() - K * H;
  P_ = IKH * P_ * IKH.transpose() + K * covariance * K.transpose();
  return true;
}

void InertialFilter::correct(const Eigen::Matrix<double, 12, 1>& dx) {
  p_ += dx.segment<3>(0);
  R_ = Eigen::Quaterniond(expSO3(dx.segment<3>(3)) * R_).normalized().toRotationMatrix();
  gyro_bias_ += dx.segment<3>(6);
  accel_bias_ += dx.segment<3>(9);
}

Eigen::Isometry3d InertialFilter::pose() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_;
  T.translation() = p_;
  return T;
}

void InertialFilter::setPose(const Eigen::Isometry3d& pose) {
  R_ = pose.linear();
  p_ = pose.translation();
}

}  // namespace radar_ndt
