// Calibrating the fusion's covariances against ground truth, and the NEES check.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "paper_tables/motion_noise.h"

using namespace radar_ndt;
using namespace radar_ndt::apps;

namespace {
/// Samples whose Doppler errors are N(0, fit + diag(s_d²)·dt²) and whose match errors are
/// N(0, k·reported) (or N(0, diag(s_m²)) without a reported covariance).
std::vector<MotionNoiseSample> samples(std::size_t n, unsigned seed, bool reported) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Vector3d s_d(0.2, 0.08, 0.03), s_m(0.04, 0.05, 0.002);
  std::vector<MotionNoiseSample> out;
  for (std::size_t i = 0; i < n; ++i) {
    MotionNoiseSample s;
    s.dt = 0.06 + 0.03 * static_cast<double>(i % 3);
    s.truth = Pose2(0.8, 0.01, 0.005);
    s.doppler_covariance = Eigen::Vector3d(1e-6, 1e-6, 1e-8).asDiagonal();
    const Eigen::Vector3d sd = (s.doppler_covariance.diagonal() + s_d.cwiseProduct(s_d) * s.dt * s.dt).cwiseSqrt();
    s.doppler = s.truth + Eigen::Vector3d(sd.x() * g(rng), sd.y() * g(rng), sd.z() * g(rng));
    s.matched = i % 10 != 0;
    const Eigen::Matrix3d reported_cov = Eigen::Vector3d(4e-4, 6e-4, 1e-6).asDiagonal();
    s.match_covariance = reported ? reported_cov : Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
    const Eigen::Vector3d sm = reported ? (3.0 * reported_cov.diagonal()).cwiseSqrt() : s_m;
    s.match = s.truth + Eigen::Vector3d(sm.x() * g(rng), sm.y() * g(rng), sm.z() * g(rng));
    out.push_back(s);
  }
  return out;
}
}  // namespace

TEST(MotionNoise, CalibrationRecoversTheNoiseAndGivesNeesThreeOnFreshSamples) {
  const MotionNoiseCalibration c = calibrateMotionNoise(samples(20000, 1, true));
  EXPECT_NEAR(c.doppler_sigma_x, 0.2, 0.01);
  EXPECT_NEAR(c.doppler_sigma_y, 0.08, 0.004);
  EXPECT_NEAR(c.doppler_sigma_yaw, 0.03, 0.0015);
  EXPECT_NEAR(c.match_covariance_scale, 3.0, 0.1);
  EXPECT_EQ(c.doppler_samples, 20000u);
  EXPECT_EQ(c.match_samples, 18000u);
  EXPECT_EQ(c.reported_covariances, 18000u);
  const MotionNees n = motionNees(samples(5000, 2, true), c.applyTo(MotionFusionOptions{}));
  EXPECT_NEAR(n.doppler, 3.0, 0.15);
  EXPECT_NEAR(n.match, 3.0, 0.15);
  // An uncalibrated fit covariance alone is far too optimistic.
  MotionFusionOptions tiny;
  tiny.doppler_sigma_x = tiny.doppler_sigma_y = tiny.doppler_sigma_yaw = 1e-6;
  EXPECT_GT(motionNees(samples(1000, 3, true), tiny).doppler, 100.0);
}

TEST(MotionNoise, WithoutReportedCovariancesTheFixedSigmasAreCalibrated) {
  const MotionNoiseCalibration c = calibrateMotionNoise(samples(20000, 4, false));
  EXPECT_EQ(c.reported_covariances, 0u);
  EXPECT_NEAR(c.match_sigma_x, 0.04, 0.002);
  EXPECT_NEAR(c.match_sigma_y, 0.05, 0.0025);
  EXPECT_NEAR(c.match_sigma_yaw, 0.002, 0.0001);
  const MotionFusionOptions o = c.applyTo(MotionFusionOptions{});
  EXPECT_EQ(o.match_covariance_scale, MotionFusionOptions{}.match_covariance_scale) << "nothing to calibrate it on";
  EXPECT_NEAR(motionNees(samples(5000, 5, false), o).match, 3.0, 0.15);
  EXPECT_THROW(calibrateMotionNoise({}), std::invalid_argument);
}

TEST(MotionNoise, MatchInformationIsTheBestLinearFusionOfIndependentErrors) {
  // Independent errors σ_d = 1 cm, σ_m = 2 cm: the best weight on the match is σ_d²/(σ_d²+σ_m²) =
  // 0.2 and the fused RMS σ_d·σ_m/√(σ_d²+σ_m²) = 0.894 cm.
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<MotionNoiseSample> v;
  for (int i = 0; i < 40000; ++i) {
    MotionNoiseSample s;
    s.dt = 0.075;
    s.truth = Pose2(0.8, 0.0, 0.0);
    s.doppler = s.truth + Eigen::Vector3d(0.01 * g(rng), 0.01 * g(rng), 0.001 * g(rng));
    s.matched = true;
    s.match = s.truth + Eigen::Vector3d(0.02 * g(rng), 0.02 * g(rng), 0.002 * g(rng));
    v.push_back(s);
  }
  const MatchInformation info = matchInformation(v);
  EXPECT_EQ(info.samples, 40000u);
  EXPECT_NEAR(info.axis[0].doppler_rms, 0.01, 2e-4);
  EXPECT_NEAR(info.axis[0].match_rms, 0.02, 4e-4);
  EXPECT_NEAR(info.axis[0].correlation, 0.0, 0.02);
  EXPECT_NEAR(info.axis[0].oracle_weight, 0.2, 0.01);
  EXPECT_NEAR(info.axis[0].oracle_rms, 0.00894, 2e-4);
  EXPECT_NEAR(info.axis[2].oracle_weight, 0.2, 0.01);

  // A match that only adds noise to the Doppler motion (it stays at its guess, as along a street
  // whose geometry runs along the track) carries nothing: weight and gain near zero.
  for (auto& s : v) s.match = s.doppler + Eigen::Vector3d(0.03 * g(rng), 0.03 * g(rng), 0.003 * g(rng));
  const MatchInformation none = matchInformation(v);
  EXPECT_NEAR(none.axis[0].oracle_weight, 0.0, 0.01);
  EXPECT_NEAR(none.axis[0].oracle_rms, none.axis[0].doppler_rms, 1e-4);
  EXPECT_GT(none.axis[0].correlation, 0.25);
  // Unmatched samples do not count; fewer than two give NaN.
  for (auto& s : v) s.matched = false;
  EXPECT_TRUE(std::isnan(matchInformation(v).axis[0].oracle_rms));
}
