#include <gtest/gtest.h>

#include "radar_ndt/se2.h"

using namespace radar_ndt;

TEST(Se2, NormalizeAngleWrapsIntoHalfOpenInterval) {
  EXPECT_NEAR(normalizeAngle(3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(normalizeAngle(-kPi), kPi, 1e-12);
  EXPECT_NEAR(normalizeAngle(0.5), 0.5, 1e-15);
  EXPECT_NEAR(normalizeAngle(-7.0), -7.0 + 2 * kPi, 1e-12);
}

TEST(Se2, ComposeInverseBetweenAgreeWithMatrices) {
  const Pose2 a(1.0, -2.0, 0.7), b(-0.3, 0.9, -2.5);
  const Eigen::Matrix4d Ma = toMatrix4<double>(a), Mb = toMatrix4<double>(b);
  EXPECT_TRUE(toPose2(Eigen::Matrix4d(Ma * Mb)).isApprox(compose(a, b), 1e-12));
  EXPECT_TRUE(toPose2(Eigen::Matrix4d(Ma.inverse())).isApprox(inverse(a), 1e-12));
  EXPECT_TRUE(between(a, compose(a, b)).isApprox(b, 1e-12));
  EXPECT_TRUE(compose(a, inverse(a)).isZero(1e-12));
}

TEST(Se2, MatrixAndIsometryConversionsRoundTrip) {
  const Pose2 p(12.5, -3.25, -1.2);
  EXPECT_TRUE(toPose2(toMatrix4<float>(p)).isApprox(p, 1e-6));
  EXPECT_TRUE(toPose2(toIsometry3(p)).isApprox(p, 1e-12));
  EXPECT_TRUE(toPose2(toIsometry2(p)).isApprox(p, 1e-12));
  const Eigen::Matrix4f M = toMatrix4<float>(p);
  EXPECT_EQ(M(2, 2), 1.0f);
  EXPECT_EQ(M(2, 3), 0.0f);
}

TEST(SE2, VelocityOfInvertsIntegrateVelocity) {
  for (const Eigen::Vector3d& v :
       {Eigen::Vector3d(10, 0.3, 0.5), Eigen::Vector3d(-2, 1, -1.2), Eigen::Vector3d(5, 0, 0)}) {
    const Eigen::Vector3d back = velocityOf(integrateVelocity(v, 0.25), 0.25);
    EXPECT_LT((back - v).norm(), 1e-9) << v.transpose();
  }
}

TEST(Se2, IntegrateVelocityIsTheArc) {
  // Quarter circle of radius 10 m: v = 10 m/s, ω = π/2 rad/s for 1 s.
  const Pose2 p = integrateVelocity(Eigen::Vector3d(10.0, 0.0, kPi / 2), 1.0);
  EXPECT_NEAR(p.x(), 20.0 / kPi, 1e-9);
  EXPECT_NEAR(p.y(), 20.0 / kPi, 1e-9);
  EXPECT_NEAR(p.z(), kPi / 2, 1e-12);
  const Pose2 straight = integrateVelocity(Eigen::Vector3d(3.0, -1.0, 0.0), 0.5);
  EXPECT_NEAR(straight.x(), 1.5, 1e-12);
  EXPECT_NEAR(straight.y(), -0.5, 1e-12);
}

TEST(Se2, InterpolateIsLinearInPositionAndTakesTheShorterArcInHeading) {
  const Pose2 a(1.0, 2.0, 0.1), b(3.0, -2.0, 0.5);
  EXPECT_EQ(interpolate(a, b, 0.0), a);
  EXPECT_TRUE(interpolate(a, b, 1.0).isApprox(b, 1e-15));
  EXPECT_TRUE(interpolate(a, b, 0.25).isApprox(Pose2(1.5, 1.0, 0.2), 1e-15));
  // Across ±π: from 170° to −170° through 180°, not back through 0.
  const Pose2 c(0, 0, 170.0 * kPi / 180.0), d(0, 0, -170.0 * kPi / 180.0);
  EXPECT_NEAR(std::abs(interpolate(c, d, 0.5).z()), kPi, 1e-12);
  EXPECT_NEAR(interpolate(c, d, 0.25).z(), 175.0 * kPi / 180.0, 1e-12);
  EXPECT_NEAR(interpolate(c, d, 0.75).z(), -175.0 * kPi / 180.0, 1e-12);
}
