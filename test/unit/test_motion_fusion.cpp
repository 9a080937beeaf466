// MotionFusion: the Doppler motion and a match fused by their covariances (a Kalman update), and
// the Doppler yaw-rate bias learned from the matches.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "radar_ndt/odometry/motion_fusion.h"

using namespace radar_ndt;

namespace {
MotionFusionOptions noBias() {
  MotionFusionOptions o;
  o.yaw_rate_bias_sigma = 0;
  o.yaw_rate_bias_walk = 0;
  return o;
}
}  // namespace

TEST(MotionFusion, TwoMeasurementsWithKnownCovariancesGiveTheKnownFusedAnswer) {
  MotionFusionOptions o = noBias();
  o.doppler_sigma_x = o.doppler_sigma_y = o.doppler_sigma_yaw = 1e-9;  // the fit's covariance alone
  MotionFusion f(o);
  const double dt = 0.1;
  // Doppler: x = 1.0 with σ² = 0.01²; match: x = 1.1 with σ² = 0.03². Fused x = 1 + 0.1 · 1/(1 + 9).
  const Eigen::Matrix3d cd = Eigen::Vector3d(1e-4, 4e-4, 1e-6).asDiagonal();
  const Eigen::Matrix3d cm = Eigen::Vector3d(9e-4, 4e-4, 3e-6).asDiagonal();
  const MotionEstimate prior = f.predict(Pose2(1.0, 0.0, 0.0), cd, dt);
  EXPECT_TRUE(prior.motion.isApprox(Pose2(1.0, 0.0, 0.0)));
  EXPECT_TRUE(prior.covariance.isApprox(cd, 1e-9));
  const MotionEstimate fused = f.update(Pose2(1.1, 0.2, 0.004), cm);
  EXPECT_NEAR(fused.motion.x(), 1.01, 1e-9);
  EXPECT_NEAR(fused.motion.y(), 0.1, 1e-9);    // equal variances: the mean
  EXPECT_NEAR(fused.motion.z(), 0.001, 1e-9);  // 1e-6 vs 3e-6: a quarter of the way to the match
  EXPECT_NEAR(fused.covariance(0, 0), 1.0 / (1.0 / 1e-4 + 1.0 / 9e-4), 1e-12);
  EXPECT_NEAR(fused.covariance(1, 1), 2e-4, 1e-12);
  EXPECT_NEAR(fused.covariance(2, 2), 0.75e-6, 1e-12);
  EXPECT_EQ(f.yawRateBias(), 0.0) << "no bias state: nothing learned";
}

TEST(MotionFusion, CalibratedNoiseIsAddedPerSecondOfMotion) {
  MotionFusionOptions o = noBias();
  o.doppler_sigma_x = 0.2;
  o.doppler_sigma_y = 0.1;
  o.doppler_sigma_yaw = 0.02;
  const MotionFusion f(o);
  const Eigen::Matrix3d fit = Eigen::Matrix3d::Identity() * 1e-6;
  const Eigen::Matrix3d c = f.dopplerCovariance(fit, 0.05);
  EXPECT_NEAR(c(0, 0), 1e-6 + 0.04 * 0.0025, 1e-15);
  EXPECT_NEAR(c(1, 1), 1e-6 + 0.01 * 0.0025, 1e-15);
  EXPECT_NEAR(c(2, 2), 1e-6 + 0.0004 * 0.0025, 1e-15);
  EXPECT_EQ(c(0, 1), 0.0);
}

TEST(MotionFusion, MatchCovarianceIsTheReportedOneScaledElseTheFixedOne) {
  MotionFusionOptions o;
  o.match_covariance_scale = 2.0;
  const MotionFusion f(o);
  const Eigen::Matrix3d reported = Eigen::Vector3d(1e-4, 2e-4, 1e-6).asDiagonal();
  EXPECT_TRUE(f.matchCovariance(&reported).isApprox(2.0 * reported));
  const Eigen::Matrix3d fixed = Eigen::Vector3d(o.match_sigma_x * o.match_sigma_x, o.match_sigma_y * o.match_sigma_y,
                                                o.match_sigma_yaw * o.match_sigma_yaw)
                                    .asDiagonal();
  EXPECT_TRUE(f.matchCovariance(nullptr).isApprox(fixed));
  const Eigen::Matrix3d nan = Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  EXPECT_TRUE(f.matchCovariance(&nan).isApprox(fixed)) << "a matcher without one reports NaN";
  const Eigen::Matrix3d degenerate = Eigen::Matrix3d::Zero();
  EXPECT_TRUE(f.matchCovariance(&degenerate).isApprox(fixed));
}

TEST(MotionFusion, LearnsAConstantDopplerYawRateBiasFromTheMatches) {
  // The Doppler yaw rate reads 0.02 rad/s too high; the matches are exact. The bias estimate
  // converges to 0.02 and the fused yaw to the truth; with the bias state off, the fused yaw keeps
  // a share of the error at every cycle.
  const double dt = 0.075, bias = 0.02, w = 0.1;
  const Eigen::Matrix3d fit = Eigen::Matrix3d::Identity() * 1e-8;
  const Eigen::Matrix3d match_cov = Eigen::Vector3d(0.04 * 0.04, 0.04 * 0.04, 0.0015 * 0.0015).asDiagonal();
  MotionFusion with_bias{MotionFusionOptions{}};
  MotionFusion without{noBias()};
  MotionEstimate a, b;
  for (int k = 0; k < 400; ++k) {
    const Pose2 truth(0.75, 0.0, w * dt);
    const Pose2 doppler(0.75, 0.0, (w + bias) * dt);
    with_bias.predict(doppler, fit, dt);
    a = with_bias.update(truth, match_cov);
    without.predict(doppler, fit, dt);
    b = without.update(truth, match_cov);
  }
  EXPECT_NEAR(with_bias.yawRateBias(), bias, 1e-3);
  EXPECT_NEAR(a.motion.z(), w * dt, 1e-4);
  EXPECT_GT(std::abs(b.motion.z() - w * dt), 5e-4) << "without the bias state a share of the error stays";
  // No match: the prediction, with the learned bias taken out.
  const MotionEstimate p = with_bias.predict(Pose2(0.75, 0.0, (w + bias) * dt), fit, dt);
  EXPECT_NEAR(p.motion.z(), w * dt, 1e-4);
  with_bias.reset();
  EXPECT_EQ(with_bias.yawRateBias(), 0.0);
}

TEST(MotionFusion, RefusesSettingsOutOfRange) {
  MotionFusionOptions o;
  o.doppler_sigma_x = 0;
  EXPECT_THROW(MotionFusion{o}, std::invalid_argument);
  o = MotionFusionOptions{};
  o.match_covariance_scale = -1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = MotionFusionOptions{};
  o.yaw_rate_bias_walk = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(o.validate(), std::invalid_argument);
  EXPECT_NO_THROW(noBias().validate());
}
