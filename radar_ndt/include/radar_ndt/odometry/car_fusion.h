#pragma once
// The car's own motion sensors fused with the radar (beyond the paper; the paper names IMU fusion
// as its future work). A car knows its motion without radar: a yaw-rate gyro and wheel speeds on
// its CAN bus. Their errors are of another kind than the radar's: the gyro's yaw is smooth but
// drifts with a slowly varying bias; the wheels' distance is smooth but off by a scale (the tyre's
// radius, its wear and pressure). So, per cycle, a small Kalman filter whose state is the cycle's
// motion (x, y, yaw), the yaw source's bias b (rad/s) and the wheels' scale s:
//  - prediction: the yaw from the gyro, θ_g − b·dt (without a gyro: the Doppler motion's yaw with
//    its yaw-rate bias, as MotionFusion); the translation along the arc of length s·d_w the rear
//    wheels rolled (without wheels: the Doppler motion's translation);
//  - with wheels, the Doppler translation is a measurement (it observes the scale);
//  - the match updates the motion, and through it the bias and the scale.
// b and s walk slowly from cycle to cycle, and are estimated online from the radar, never from
// the ground truth. Without the radar's updates (the wheel-gyro method) this is the car's own dead
// reckoning at the nominal wheel radius.

#include <Eigen/Core>

#include "radar_ndt/fields.h"
#include "radar_ndt/odometry/motion_fusion.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

struct CarSensorOptions {
  bool gyro = false;            ///< fuse the car's yaw-rate gyro
  bool wheels = false;          ///< fuse the car's rear wheel speeds
  double wheel_radius = 0.305;  ///< m: rpm × 2π r / 60 is the speed
  double time_offset = 0.0;     ///< s: the CAN clock minus the radar clock
  /// The gyro's angle random walk (rad/√s), its bias at the start (1σ, rad/s) and the bias's walk
  /// (rad/s per √s).
  double gyro_noise = 0.0015;
  double gyro_bias_sigma = 0.005;
  double gyro_bias_walk = 0.0005;
  /// The wheels' speed noise (m/s, 1σ per cycle's mean speed), their scale's 1σ at the start and
  /// its walk (per √s).
  double wheel_noise = 0.02;
  double wheel_scale_sigma = 0.01;
  double wheel_scale_walk = 0.0001;
  bool any() const { return gyro || wheels; }
  /// Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void CarSensorOptions::fields(Visit&& visit) {
  using S = CarSensorOptions;
  visit(&S::gyro, Field("gyro", "fuse the car's yaw-rate gyro")
                      .onSwitch("imu", "fuse the car's yaw-rate gyro (nuScenes: can_bus/<scene>_ms_imu.json)"));
  visit(&S::wheels,
        Field("wheels", "fuse the car's rear wheel speeds")
            .onSwitch("wheels", "fuse the car's rear wheel speeds (nuScenes: can_bus/<scene>_zoe_veh_info.json)"));
  visit(&S::wheel_radius, Field("wheel_radius", "the wheels' nominal radius").unit("m").positive().cli("wheel-radius"));
  visit(&S::time_offset,
        Field("time_offset", "the CAN bus clock minus the radar clock").unit("s").cli("can-time-offset"));
  visit(&S::gyro_noise, Field("gyro_noise", "the gyro's angle random walk").unit("rad/√s").positive());
  visit(&S::gyro_bias_sigma, Field("gyro_bias_sigma", "the gyro's bias: 1σ at the start").unit("rad/s").atLeast(0));
  visit(&S::gyro_bias_walk, Field("gyro_bias_walk", "... and its random walk").unit("rad/s/√s").atLeast(0));
  visit(&S::wheel_noise, Field("wheel_noise", "the wheels' speed noise, 1σ").unit("m/s").positive());
  visit(&S::wheel_scale_sigma, Field("wheel_scale_sigma", "the wheels' scale: 1σ at the start").atLeast(0));
  visit(&S::wheel_scale_walk, Field("wheel_scale_walk", "... and its random walk").unit("1/√s").atLeast(0));
}

/// What the car's sensors measured over one cycle's interval.
struct CarMotion {
  bool has_yaw = false;
  double yaw = 0;  ///< rad, the gyro's yaw rate integrated
  bool has_distance = false;
  double distance = 0;  ///< m, at the nominal wheel radius
};

class CarFusion {
 public:
  CarFusion(const CarSensorOptions& car, const MotionFusionOptions& doppler);

  /// The prediction from the car's sensors (and the Doppler motion where they measure nothing),
  /// then, with wheels and `doppler_update`, the Doppler translation fused: the prior and the
  /// matcher's initial guess. Adds the bias's and the scale's walk over dt.
  MotionEstimate predict(const CarMotion& car, const Pose2& doppler_motion, const Eigen::Matrix3d& doppler_fit_cov,
                         double dt, bool doppler_update);
  /// Fuses the last prediction with a match of covariance `match_covariance`.
  MotionEstimate update(const Pose2& match, const Eigen::Matrix3d& match_covariance);

  double bias() const { return x_(3); }
  double wheelScale() const { return x_(4); }
  void reset();

 private:
  /// Kalman update of the state by z = H x + noise(R).
  void correct(const Eigen::MatrixXd& H, const Eigen::VectorXd& z, const Eigen::MatrixXd& R, bool yaw_in_z);
  MotionEstimate estimate() const;

  CarSensorOptions car_;
  MotionFusion doppler_;  ///< the Doppler motion's calibrated covariance
  using Vector5d = Eigen::Matrix<double, 5, 1>;
  using Matrix5d = Eigen::Matrix<double, 5, 5>;
  Vector5d x_;  ///< motion (x, y, yaw), bias, scale
  Matrix5d P_;
};

}  // namespace radar_ndt
