#pragma once
// Fusing the Doppler ego-motion with a scan match (beyond the paper). The Doppler ego-velocity
// integral (Kellner et al.; the paper's Sec. III-B prior) measures each cycle's translation well
// but its yaw drifts: its yaw errors are correlated from cycle to cycle (a yaw-rate bias that
// varies slowly), while a match against a map the odometry already placed is anchored to that
// map and its errors do not accumulate. So the fusion is a small Kalman filter per cycle:
//  - state: the cycle's motion (x, y, yaw) and the Doppler yaw-rate bias b (rad/s), which is
//    carried from cycle to cycle as a random walk;
//  - prediction: the Doppler motion with its yaw corrected by b·dt; its covariance is the
//    ego-velocity fit's plus a calibrated noise per axis (the fit treats detections as
//    independent and is far too optimistic), plus the bias's;
//  - update: the match with its calibrated covariance; the innovation corrects the motion and
//    the bias together.
// Without a match (dead reckoning, fallback) the prediction is the motion and the bias keeps its
// estimate.

#include <Eigen/Core>

#include "radar_ndt/fields.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

struct MotionFusionOptions {
  /// Noise of the Doppler motion beyond the ego-velocity fit's covariance, 1σ per second of motion
  /// along x, y (m/s) and in yaw (rad/s): added as diag(σ²)·dt². Calibrated against ground-truth
  /// motions (docs/automotive_pipeline.md, "Calibrated covariances").
  double doppler_sigma_x = 0.18;
  double doppler_sigma_y = 0.07;
  double doppler_sigma_yaw = 0.024;
  // How far a match is trusted, calibrated per matcher on the shared nuScenes scenes
  // (radar_paper_tables --noise-calibration; docs/automotive_pipeline.md); the odometry picks the
  // calibration of the matcher it was given (MatchCalibration).
  /// Ours reports a pose covariance (the inverse weighted information, which treats points as
  /// independent): that covariance times this factor.
  double match_covariance_scale = 2.2;
  /// Ours with Rapp's Doppler weights: its covariance times this factor (the weights make the
  /// information less optimistic).
  double rapp_covariance_scale = 1.23;
  /// A matcher that reports none and has a grid resolution (PCL's NDT): diag(σ²) with these 1σ
  /// (m, m, rad).
  double match_sigma_x = 0.040;
  double match_sigma_y = 0.046;
  double match_sigma_yaw = 0.0017;
  /// Any other matcher without a covariance (PCL's ICP): diag(σ²) with these 1σ (m, m, rad).
  double icp_sigma_x = 0.074;
  double icp_sigma_y = 0.071;
  double icp_sigma_yaw = 0.0021;
  /// Yaw-rate bias: 1σ at the start (rad/s) and its random walk (rad/s per √s). 0 and 0: no bias
  /// state (plain information-weighted fusion of the two motions).
  double yaw_rate_bias_sigma = 0.01;
  double yaw_rate_bias_walk = 0.003;
  /// Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void MotionFusionOptions::fields(Visit&& visit) {
  using S = MotionFusionOptions;
  visit(&S::doppler_sigma_x, Field("doppler_sigma_x", "the Doppler motion's noise along x").unit("m/s").positive());
  visit(&S::doppler_sigma_y, Field("doppler_sigma_y", "... along y").unit("m/s").positive());
  visit(&S::doppler_sigma_yaw, Field("doppler_sigma_yaw", "... in yaw").unit("rad/s").positive());
  visit(&S::match_covariance_scale,
        Field("match_covariance_scale", "pw-ndt's reported covariance times this").positive());
  visit(&S::rapp_covariance_scale,
        Field("rapp_covariance_scale", "rapp-ndt's reported covariance times this").positive());
  visit(&S::match_sigma_x,
        Field("match_sigma_x", "a gridded matcher without a covariance (pcl-ndt): 1σ along x").unit("m").positive());
  visit(&S::match_sigma_y, Field("match_sigma_y", "... along y").unit("m").positive());
  visit(&S::match_sigma_yaw, Field("match_sigma_yaw", "... in yaw").unit("rad").positive());
  visit(&S::icp_sigma_x,
        Field("icp_sigma_x", "any other matcher without a covariance (pcl-icp): 1σ along x").unit("m").positive());
  visit(&S::icp_sigma_y, Field("icp_sigma_y", "... along y").unit("m").positive());
  visit(&S::icp_sigma_yaw, Field("icp_sigma_yaw", "... in yaw").unit("rad").positive());
  visit(&S::yaw_rate_bias_sigma,
        Field("yaw_rate_bias_sigma", "the Doppler yaw-rate bias: 1σ at the start").unit("rad/s").atLeast(0));
  visit(&S::yaw_rate_bias_walk, Field("yaw_rate_bias_walk", "... and its random walk").unit("rad/s/√s").atLeast(0));
}

/// Which calibration of MotionFusionOptions a match is fused with: the matcher that made it.
enum class MatchCalibration {
  WeightedNdt,  ///< its reported covariance × match_covariance_scale (pw-ndt)
  Rapp,         ///< WeightedNDT2D with Doppler weights: × rapp_covariance_scale (rapp-ndt)
  PclNdt,       ///< no covariance: match_sigma_*
  PclIcp,       ///< no covariance: icp_sigma_*
};

/// A motion and its covariance.
struct MotionEstimate {
  Pose2 motion = Pose2::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

class MotionFusion {
 public:
  explicit MotionFusion(const MotionFusionOptions& options = {});

  /// The Doppler motion over `dt` s (the ego-velocity integral) and its fit's covariance, with the
  /// yaw corrected by the bias and the calibrated noise and the bias's uncertainty added: the
  /// prediction and the matcher's initial guess. Adds the bias's random walk over dt.
  MotionEstimate predict(const Pose2& doppler_motion, const Eigen::Matrix3d& doppler_fit_covariance, double dt);
  /// Fuses the last prediction with a match of covariance `match_covariance`; updates the bias.
  MotionEstimate update(const Pose2& match, const Eigen::Matrix3d& match_covariance);
  /// The covariance a match is fused with: `reported` × the calibration's scale when the matcher
  /// reported one (finite, positive definite), else the calibration's fixed σ's.
  Eigen::Matrix3d matchCovariance(const Eigen::Matrix3d* reported,
                                  MatchCalibration calibration = MatchCalibration::WeightedNdt) const;
  /// The Doppler motion's calibrated covariance: fit covariance + diag(σ²)·dt².
  Eigen::Matrix3d dopplerCovariance(const Eigen::Matrix3d& doppler_fit_covariance, double dt) const;

  double yawRateBias() const { return bias_; }
  double yawRateBiasVariance() const { return bias_var_; }
  void reset();
  const MotionFusionOptions& options() const { return options_; }

 private:
  MotionFusionOptions options_;
  double bias_ = 0, bias_var_ = 0;
  // The last prediction: motion and the joint covariance of (motion, bias).
  Pose2 predicted_ = Pose2::Zero();
  Eigen::Matrix4d joint_ = Eigen::Matrix4d::Zero();
};

}  // namespace radar_ndt
