#include <gtest/gtest.h>

#include "radar_ndt/se2.h"

using namespace radar_ndt;

TEST(Se2, NormalizeAngleWrapsIntoHalfOpenInterval) {
  EXPECT_NEAR(normalizeAngle(3 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(normalizeAngle(-M_PI), M_PI, 1e-12);
  EXPECT_NEAR(normalizeAngle(0.5), 0.5, 1e-15);
  EXPECT_NEAR(normalizeAngle(-7.0), -7.0 + 2 * M_PI, 1e-12);
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
