#pragma once
// The IMU half of the 6-DoF radar odometry: an error-state Kalman filter (as the radar-inertial
// odometry of Doer and Trommer 2020 and FAST-LIO keep one) over the body's pose and the IMU's
// biases. Error state δx = (δp, δθ, δb_g, δb_a): the position in the world, the world-frame
// rotation error (R_true = Exp(δθ) R), the gyro's and the accelerometer's biases. Between scans
// the gyro turns R and the Doppler body velocity (ego_velocity_3d.h) moves p, so the prior a scan
// is matched from is what the doppler-imu baseline knows; three corrections then pull the state:
//  - gravity: the accelerometer less the body's own acceleration (dv/dt + ω × v from the Doppler
//    velocity and the gyro) reads R⁻¹ g ẑ + b_a; its residual R (f − b_a − a) − g ẑ
//    ≈ g [ẑ]× δθ + R δb_a holds roll and pitch and the accelerometer's bias, nothing else
//    (what is left of the body's acceleration in it must not leak into yaw or the gyro's bias);
//    the gyro's bias is the still start's;
//  - the matched pose against the local map (the 3D matcher's pose and covariance): the pose
//    components it measures, and only those (a Schmidt update: the biases and the components it
//    leaves to the IMU are not moved through their correlations);
//  - a gate: a match whose Mahalanobis distance to the prior exceeds `match_gate` is refused.
// The IMU's noise figures are a MEMS grade's (the rio rig's ADIS16448 class) by default.

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/imu_sample.h"

namespace radar_ndt {

struct InertialFilterOptions {
  double gravity = 9.81;              ///< m/s²
  double gyro_noise = 2e-4;           ///< rad/s/√Hz: the gyro's angle random walk
  double gyro_bias_walk = 1e-5;       ///< rad/s/√s
  double accel_noise = 2e-3;          ///< m/s²/√Hz
  double accel_bias_walk = 1e-4;      ///< m/s²/√s
  double initial_gyro_bias = 0.005;   ///< rad/s, 1σ: what the still start leaves unknown
  double initial_accel_bias = 0.05;   ///< m/s², 1σ
  double initial_attitude_deg = 1.0;  ///< deg, 1σ: roll and pitch from the still start
  double gravity_sigma = 0.2;         ///< m/s², 1σ: a scan interval's mean specific force less
                                      ///< the body's acceleration, as a reading of gravity
  double still_tolerance = 0.5;       ///< m/s²: | |f − a| − g | above it, no gravity update
  double initial_seconds = 0.5;       ///< s of IMU at the start: roll, pitch, the gyro's bias
  double match_gate = 22.46;          ///< χ²(6) at 99.9 %: a farther match is refused
  /// Throws std::invalid_argument naming the setting out of range.
  void validate() const;
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void InertialFilterOptions::fields(Visit&& visit) {
  using S = InertialFilterOptions;
  visit(&S::gravity, Field("gravity", "the local gravity").unit("m/s^2").positive());
  visit(&S::gyro_noise, Field("gyro_noise", "the gyro's white noise").unit("rad/s/sqrt(Hz)").positive());
  visit(&S::gyro_bias_walk, Field("gyro_bias_walk", "the gyro bias's random walk").unit("rad/s/sqrt(s)").atLeast(0));
  visit(&S::accel_noise, Field("accel_noise", "the accelerometer's white noise").unit("m/s^2/sqrt(Hz)").positive());
  visit(&S::accel_bias_walk,
        Field("accel_bias_walk", "the accelerometer bias's random walk").unit("m/s^2/sqrt(s)").atLeast(0));
  visit(&S::initial_gyro_bias,
        Field("initial_gyro_bias", "1 sigma of the gyro bias the still start leaves").unit("rad/s").positive());
  visit(&S::initial_accel_bias,
        Field("initial_accel_bias", "1 sigma of the accelerometer bias at the start").unit("m/s^2").positive());
  visit(&S::initial_attitude_deg,
        Field("initial_attitude_deg", "1 sigma of roll and pitch from the still start").unit("deg").positive());
  visit(&S::gravity_sigma,
        Field("gravity_sigma", "1 sigma of a scan interval's accelerometer as gravity").unit("m/s^2").positive());
  visit(&S::still_tolerance,
        Field("still_tolerance", "| |f - a| - g | above which gravity is not read").unit("m/s^2").positive());
  visit(&S::initial_seconds,
        Field("initial_seconds", "IMU at the start that gives roll, pitch and the gyro's bias").unit("s").positive());
  visit(&S::match_gate,
        Field("match_gate", "a match farther from the prior (chi-square, 6 DoF) is refused").positive());
}

/// What a still start tells: roll and pitch (yaw zero) and, when the rig was still, the gyro's bias.
struct StillStart {
  Eigen::Matrix3d attitude = Eigen::Matrix3d::Identity();  ///< body to world, the world's z up
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();     ///< rad/s; zero when not still
  bool still = false;
};

/// Reads the first `seconds` of `imu` (time-ordered, body axes, not empty): the mean specific
/// force levels the body, the mean gyro is the bias if the rig was still. Says in `problems` when
/// the accelerometer's gravity is more than 45° off the body's z (the IMU's axes are not what the
/// description says) or the rig was not still.
StillStart readStillStart(const std::vector<ImuSample>& imu, double seconds, double gravity,
                          std::vector<std::string>& problems);

/// Error-state order (δp, δθ, δb_g, δb_a), as the 3D matchers' perturbation (v, ω) then the biases.
using Matrix12d = Eigen::Matrix<double, 12, 12>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

class InertialFilter {
 public:
  /// Validates `o` (std::invalid_argument).
  explicit InertialFilter(const InertialFilterOptions& o = {});
  const InertialFilterOptions& options() const { return options_; }

  /// Roll, pitch and the gyro's bias from the first initial_seconds of `imu` (time-ordered, in
  /// the body's axes); yaw and position zero. Problems (gravity far from the body's z, a start
  /// that was not still) are added to `problems`. std::invalid_argument without a message.
  void initialize(const std::vector<ImuSample>& imu, std::vector<std::string>& problems);
  bool initialized() const { return initialized_; }
  /// Whether the IMU's first initial_seconds were still (the rig then known to stand at the start).
  bool stillStart() const { return still_start_; }

  /// Moves the state over [a.t, b.t]: the gyro's mean turns R; p moves by R v dt with `velocity`
  /// (body axes, m/s) and its covariance `velocity_covariance` taken as constant over `interval`
  /// (s: the scan interval the velocity holds for, so that its error adds up over it).
  void predict(const ImuSample& a, const ImuSample& b, const Eigen::Vector3d& velocity,
               const Eigen::Matrix3d& velocity_covariance, double interval);
  /// The accelerometer's mean `specific_force` (body axes) over an interval less the body's own
  /// `acceleration` (body axes, with its covariance) read as gravity. False (no update) outside
  /// still_tolerance.
  bool updateGravity(const Eigen::Vector3d& specific_force, const Eigen::Vector3d& acceleration,
                     const Eigen::Matrix3d& acceleration_covariance = Eigen::Matrix3d::Zero());
  /// A measured pose with its 6x6 covariance in (v, ω) (the pose moved to (Exp(ω) R, p + v)).
  /// Only the components flagged in `measured_axes` (x, y, z, then the rotations about the
  /// world's x, y, z) are corrected; the biases never are (a Schmidt update). False (state
  /// untouched) when its squared Mahalanobis distance to the prediction exceeds match_gate or
  /// the covariance is not usable; `distance` (optional) gets that distance.
  bool updatePose(const Eigen::Isometry3d& measured, const Matrix6d& covariance,
                  const std::array<bool, 6>& measured_axes = {true, true, true, true, true, true},
                  double* distance = nullptr);

  Eigen::Isometry3d pose() const;
  void setPose(const Eigen::Isometry3d& pose);
  const Eigen::Vector3d& gyroBias() const { return gyro_bias_; }
  const Eigen::Vector3d& accelBias() const { return accel_bias_; }
  /// The pose's 6x6 block of the covariance, (δp, δθ).
  Matrix6d poseCovariance() const { return P_.topLeftCorner<6, 6>(); }
  const Matrix12d& covariance() const { return P_; }

 private:
  void correct(const Eigen::Matrix<double, 12, 1>& dx);
  InertialFilterOptions options_;
  bool initialized_ = false;
  bool still_start_ = false;
  Eigen::Matrix3d R_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_bias_ = Eigen::Vector3d::Zero(), accel_bias_ = Eigen::Vector3d::Zero();
  Matrix12d P_ = Matrix12d::Identity();
};

}  // namespace radar_ndt
