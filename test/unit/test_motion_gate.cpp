// The two motion gates: the automotive one (a·dt² against the rescaled last displacement, and a
// chi-square test against the Doppler motion) and the scanning one (a·Δt·dt against the last
// trusted velocity, with a yaw bound).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "radar_ndt/odometry/motion_gate.h"

using namespace radar_ndt;

TEST(AutomotiveMotionGate, BoundsTheAccelerationThenTestsAgreementWithTheDopplerMotion) {
  AutomotiveMotionGate gate;
  ConstantVelocityModel prior;
  prior.update(Pose2(1.0, 0.0, 0.0), 0.1);  // 10 m/s
  const double dt = 0.1;
  const Eigen::Matrix3d cov = Eigen::Vector3d(1e-4, 1e-4, 1e-6).asDiagonal();
  double chi2 = -1;
  // The bound: 8 m/s² · dt² + 3·√2·5 cm = 0.08 + 0.2121 m from the expected 1.0 m.
  EXPECT_TRUE(gate.accept(Pose2(1.0, 0.0, 0.0), Pose2(1.0, 0.0, 0.0), cov, dt, prior, &chi2));
  EXPECT_EQ(chi2, 0.0);
  EXPECT_FALSE(gate.accept(Pose2(1.30, 0.0, 0.0), Pose2(1.30, 0.0, 0.0), cov, dt, prior, &chi2))
      << "0.30 m off the prior";
  EXPECT_TRUE(std::isinf(chi2));
  EXPECT_TRUE(gate.accept(Pose2(1.28, 0.0, 0.0), Pose2(1.28, 0.0, 0.0), cov, dt, prior, &chi2)) << "0.28 m: within";
  // Chi-square: r = (0.1, 0, 0) with S = diag(1e-4 + 0.0025, …): 0.01 / 0.0026 = 3.85 (under 16.27).
  EXPECT_TRUE(gate.accept(Pose2(1.1, 0.0, 0.0), Pose2(1.0, 0.0, 0.0), cov, dt, prior, &chi2));
  EXPECT_NEAR(chi2, 0.01 / 0.0026, 1e-9);
  // 0.25 m off the Doppler motion: 0.0625 / 0.0026 = 24 > 16.27.
  EXPECT_FALSE(gate.accept(Pose2(1.25, 0.0, 0.0), Pose2(1.0, 0.0, 0.0), cov, dt, prior, &chi2));
  EXPECT_NEAR(chi2, 0.0625 / 0.0026, 1e-9);
  // Rotation enters the chi-square only: 0.02 rad against σ² 1e-6 + 2.5e-5 passes, 0.021 does not.
  EXPECT_TRUE(gate.accept(Pose2(1.0, 0.0, 0.02), Pose2(1.0, 0.0, 0.0), cov, dt, prior, &chi2));
  EXPECT_NEAR(chi2, 0.0004 / 2.6e-5, 1e-6);
  EXPECT_FALSE(gate.accept(Pose2(1.0, 0.0, 0.021), Pose2(1.0, 0.0, 0.0), cov, dt, prior, &chi2));
  EXPECT_NEAR(chi2, 0.000441 / 2.6e-5, 1e-6);
}

TEST(AutomotiveMotionGate, WithoutAPriorOnlyTheChiSquareAndDisabledAcceptsAll) {
  const ConstantVelocityModel none;  // the first match: no displacement to compare with
  const Eigen::Matrix3d cov = Eigen::Matrix3d::Identity() * 1e-4;
  double chi2 = 0;
  AutomotiveMotionGate gate;
  EXPECT_TRUE(gate.accept(Pose2(5.0, 0.0, 0.0), Pose2(5.0, 0.0, 0.0), cov, 0.1, none, &chi2));
  AutomotiveMotionGateOptions off;
  off.enabled = false;
  EXPECT_TRUE(AutomotiveMotionGate(off).accept(Pose2(50.0, 9.0, 1.0), Pose2(1.0, 0.0, 0.0), cov, 0.1, none, &chi2));
  EXPECT_EQ(chi2, 0.0);
  AutomotiveMotionGateOptions bad;
  bad.chi2_threshold = 0;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

TEST(ScanningMotionGate, BoundsTheVelocityChangeOverTheTimeSinceTheLastTrustedMatch) {
  ScanningMotionGate gate;
  const double dt = 0.25;
  EXPECT_TRUE(gate.accept(Pose2(100.0, 0.0, 3.0), dt, 0.125)) << "nothing trusted yet";
  gate.trust(Pose2(2.5, 0.0, 0.0), dt, 0.125);  // 10 m/s, centred at 0.125 s
  // The next interval (middle 0.375 s): Δt = 0.25 s, bound 8·0.25·0.25 + 0.2121 = 0.7121 m.
  EXPECT_TRUE(gate.accept(Pose2(3.2, 0.0, 0.0), dt, 0.375));
  EXPECT_FALSE(gate.accept(Pose2(3.25, 0.0, 0.0), dt, 0.375));
  // After fallbacks the bound grows with the time since the trusted match: Δt = 1 s, 2.2121 m.
  EXPECT_TRUE(gate.accept(Pose2(4.7, 0.0, 0.0), dt, 1.125));
  EXPECT_FALSE(gate.accept(Pose2(4.75, 0.0, 0.0), dt, 1.125));
  // Yaw: 4 rad/s² · 0.25 · 0.25 + 3·√2·0.005 = 0.2712 rad.
  EXPECT_TRUE(gate.accept(Pose2(2.5, 0.0, 0.27), dt, 0.375));
  EXPECT_FALSE(gate.accept(Pose2(2.5, 0.0, 0.28), dt, 0.375));
  ScanningMotionGateOptions bad;
  bad.max_acceleration = -1;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
  ScanningMotionGateOptions none;
  none.max_acceleration = std::numeric_limits<double>::infinity();  // --no-gate: valid
  EXPECT_NO_THROW(none.validate());
}
