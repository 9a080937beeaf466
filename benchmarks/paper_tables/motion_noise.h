#pragma once
// Calibrating the covariances the automotive fusion weighs (MotionFusion) against ground-truth
// motions, and checking them: the normalised estimation error squared (NEES) e^T C^-1 e of a
// well-calibrated 3-DoF motion estimate has mean 3. Calibrated per source:
//  - the Doppler motion: its fit covariance (points treated as independent: far too small) plus
//    diag(σ²)·dt², σ per axis such that each axis's mean squared error is explained;
//  - a match with a reported covariance: that covariance times one scale (mean NEES / 3);
//  - a match without one: diag(σ²), σ² each axis's mean squared error.

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "radar_ndt/odometry/motion_fusion.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace apps {

/// One cycle's motions, as the odometry reported them, and the ground truth.
struct MotionNoiseSample {
  double dt = 0;
  Pose2 truth = Pose2::Zero();
  Pose2 doppler = Pose2::Zero();
  Eigen::Matrix3d doppler_covariance = Eigen::Matrix3d::Zero();  ///< the fit's, uncalibrated
  bool matched = false;
  Pose2 match = Pose2::Zero();
  Eigen::Matrix3d match_covariance = Eigen::Matrix3d::Zero();  ///< as reported (NaN: none)
};

/// The samples of a run with ground truth: every cycle after the first with a valid ego-velocity
/// and a finite ground-truth motion (bridged, skipped and dead-reckoned cycles give no match).
std::vector<MotionNoiseSample> motionNoiseSamples(const AutomotiveRunResult& run);

struct MotionNoiseCalibration {
  double doppler_sigma_x = 0, doppler_sigma_y = 0, doppler_sigma_yaw = 0;  ///< m/s, m/s, rad/s
  double match_covariance_scale = 0;                                 ///< 0 when no sample had a reported covariance
  double match_sigma_x = 0, match_sigma_y = 0, match_sigma_yaw = 0;  ///< m, m, rad
  std::size_t doppler_samples = 0, match_samples = 0, reported_covariances = 0;
  /// `options` with the calibrated values set for the matcher `which` (its scale or its σ's;
  /// those without samples unchanged).
  MotionFusionOptions applyTo(MotionFusionOptions options,
                              MatchCalibration which = MatchCalibration::WeightedNdt) const;
};

/// Calibrates from `samples` (throws std::invalid_argument when there are none).
MotionNoiseCalibration calibrateMotionNoise(const std::vector<MotionNoiseSample>& samples);

struct MotionNees {
  double doppler = 0, match = 0;  ///< mean NEES (NaN without samples)
  std::size_t doppler_samples = 0, match_samples = 0;
};

/// Mean NEES of the Doppler and match motions of `samples` under `options`' covariances (the
/// reported match covariance scaled when there is one, else the fixed σ's).
MotionNees motionNees(const std::vector<MotionNoiseSample>& samples, const MotionFusionOptions& options,
                      MatchCalibration which = MatchCalibration::WeightedNdt);

/// What the match can add to the Doppler motion on one axis (x, y or yaw of the motion), judged
/// with the ground truth: the two errors' RMS and correlation, and the best any fixed linear
/// fusion d + w·(m − d) could do, w chosen with the ground truth on these very samples (an
/// oracle, so an upper bound on what a fusion of these two motions can gain on this axis).
struct MatchInformationAxis {
  double doppler_rms = 0, match_rms = 0;
  double correlation = 0;    ///< of the Doppler and match errors
  double oracle_weight = 0;  ///< w* = −Σ e_d (e_m − e_d) / Σ (e_m − e_d)²
  double oracle_rms = 0;     ///< the RMS error of d + w*·(m − d)
};
struct MatchInformation {
  MatchInformationAxis axis[3];  ///< x (along track), y, yaw
  std::size_t samples = 0;       ///< matched samples used
};
/// Over the matched samples (NaN figures when there are fewer than 2).
MatchInformation matchInformation(const std::vector<MotionNoiseSample>& samples);

}  // namespace apps
}  // namespace radar_ndt
