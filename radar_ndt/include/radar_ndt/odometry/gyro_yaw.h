#pragma once
// A yaw-rate gyro in the scanning pipeline (beyond the paper; the paper names IMU fusion as its
// future work). A scan match's yaw is noisy scan to scan and its errors add up into the heading,
// which is what turns into drift; a gyro's yaw is smooth but off by a slowly wandering bias. Per
// scan, a two-state Kalman filter (the step's yaw θ and the gyro's bias b):
//  - prediction: θ = ∫ω − b·dt over the interval between the scans' reference times: the prior's
//    yaw and the matcher's initial guess; its mean rate also de-skews the sweep (the rotation
//    while the antenna turns);
//  - update: the match's yaw, unless it disagrees with the prediction beyond `gate` σ (a wrong
//    match: the gyro's yaw is kept);
//  - b walks between scans and is observed only through the matches, never the ground truth.

#include <Eigen/Core>

#include "radar_ndt/fields.h"

namespace radar_ndt {

struct GyroOptions {
  bool enabled = false;            ///< fuse a yaw-rate gyro
  double time_offset = 0.0;        ///< s: the gyro's clock minus the radar's
  double noise = 0.0005;           ///< rad/√s: the gyro's angle random walk
  double bias_sigma = 0.005;       ///< rad/s: its bias at the start, 1σ
  double bias_walk = 0.0001;       ///< rad/s/√s: the bias's random walk
  double match_yaw_sigma = 0.002;  ///< rad: a scan match's yaw error, 1σ
  double gate = 5.0;               ///< σ of the innovation beyond which a match's yaw is not fused
  bool deskew = true;              ///< the sweep's rotation taken from the gyro
  /// Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void GyroOptions::fields(Visit&& visit) {
  using S = GyroOptions;
  visit(&S::enabled,
        Field("enabled", "fuse a yaw-rate gyro").onSwitch("imu", "fuse a yaw-rate gyro (boreas: applanix/imu.csv)"));
  visit(&S::time_offset, Field("time_offset", "the gyro's clock minus the radar's").unit("s").cli("imu-time-offset"));
  visit(&S::noise, Field("noise", "the gyro's angle random walk").unit("rad/√s").positive().cli("imu-noise"));
  visit(&S::bias_sigma,
        Field("bias_sigma", "the gyro's bias: 1σ at the start").unit("rad/s").atLeast(0).cli("imu-bias-sigma"));
  visit(&S::bias_walk,
        Field("bias_walk", "the gyro bias's random walk").unit("rad/s/√s").atLeast(0).cli("imu-bias-walk"));
  visit(&S::match_yaw_sigma, Field("match_yaw_sigma", "a scan match's yaw error, 1σ").unit("rad").positive());
  visit(&S::gate, Field("gate", "a match's yaw further from the gyro's than this many σ is not fused").positive());
  visit(&S::deskew, Field("deskew", "the sweep's rotation from the gyro")
                        .offSwitch("imu-no-deskew", "with --imu: the sweep's rotation from the match (ablation)"));
}

class GyroYaw {
 public:
  explicit GyroYaw(const GyroOptions& options);
  /// The step's yaw from the gyro's integral `gyro_yaw` (rad) over `dt` (s), bias removed.
  double predict(double gyro_yaw, double dt);
  /// The match's yaw fused with the last prediction; the prediction itself when the match is
  /// beyond the gate (`*fused` false then).
  double update(double match_yaw, bool* fused = nullptr);
  double bias() const { return x_(1); }
  void reset();

 private:
  GyroOptions options_;
  Eigen::Vector2d x_;  ///< the step's yaw, the bias
  Eigen::Matrix2d P_;
};

}  // namespace radar_ndt
