// detail/point_fields.h: what the matcher reads from each point type (power, covariance), how a
// covariance turns with the point, and which points are usable.
#include <gtest/gtest.h>

#include <cmath>

#include "radar_ndt/registration/detail/point_fields.h"
#include "registration_support.h"

using namespace radar_ndt;

TEST(PointFields, PowerAndCovarianceByPointType) {
  const PointRadar radar = test::pointWith(1.0f, 2.0f, 0.6f, 0.04f, 0.01f, 0.09f);
  pcl::PointXYZI xyzi;
  xyzi.x = 1.0f;
  xyzi.intensity = 0.3f;
  const pcl::PointXYZ xyz(1.0f, 2.0f, 0.0f);
  EXPECT_EQ(detail::pointPower(radar), 0.6f);
  EXPECT_EQ(detail::pointPower(xyzi), 0.3f);
  EXPECT_EQ(detail::pointPower(xyz), 1.0f);
  EXPECT_EQ(detail::pointCovariance(radar), Eigen::Vector3d(0.04f, 0.01f, 0.09f));
  EXPECT_EQ(detail::pointCovariance(xyzi), Eigen::Vector3d::Zero());
  EXPECT_EQ(detail::pointCovariance(xyz), Eigen::Vector3d::Zero());
}

TEST(PointFields, ACovarianceTurnsWithThePoint) {
  // A covariance long along x, turned by 90°: long along y, the correlation's sign flipped.
  PointRadar p = test::pointWith(0.0f, 0.0f, 1.0f, 0.09f, 0.01f, 0.01f);
  detail::rotateCovariance(p, Eigen::Rotation2Dd(kPi / 2).toRotationMatrix());
  EXPECT_NEAR(p.cov_xx, 0.01f, 1e-7);
  EXPECT_NEAR(p.cov_yy, 0.09f, 1e-7);
  EXPECT_NEAR(p.cov_xy, -0.01f, 1e-7);
  pcl::PointXYZ xyz(1.0f, 0.0f, 0.0f);  // no covariance: untouched
  detail::rotateCovariance(xyz, Eigen::Rotation2Dd(1.0).toRotationMatrix());
  EXPECT_EQ(xyz.x, 1.0f);
}

TEST(PointFields, UsablePointsAreFiniteWithVariancesNotNegative) {
  EXPECT_TRUE(detail::usable(1.0, 2.0, Eigen::Vector3d(0.1, -0.05, 0.1)));
  EXPECT_FALSE(detail::usable(std::nan(""), 2.0, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(detail::usable(1.0, INFINITY, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(detail::usable(1.0, 2.0, Eigen::Vector3d(-0.1, 0.0, 0.1)));
  EXPECT_FALSE(detail::usable(1.0, 2.0, Eigen::Vector3d(0.1, 0.0, -0.1)));
  EXPECT_FALSE(detail::usable(1.0, 2.0, Eigen::Vector3d(0.1, std::nan(""), 0.1)));
  EXPECT_EQ(detail::floorToInt(-0.5), -1);
  EXPECT_EQ(detail::floorToInt(2.999), 2);
}
