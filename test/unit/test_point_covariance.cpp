// frontend/point_covariance.h: the ARS408 polar model's covariance as numbers, how it grows with
// range and azimuth, its turn into the vehicle frame, and the reported rms used where present.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "radar_ndt/frontend/point_covariance.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

namespace {
constexpr double kDeg = kPi / 180.0;
}

TEST(PointCovariance, PolarModelIsTheRangeAndAzimuthSigmasThroughTheJacobian) {
  const PolarAccuracy a;
  // Straight ahead at 20 m: σ along x is the near range σ (0.10 m), across it 20 m · 0.1°.
  Eigen::Matrix2d C = polarCovariance(20.0, 0.0, a);
  EXPECT_NEAR(C(0, 0), 0.10 * 0.10, 1e-12);
  EXPECT_NEAR(C(1, 1), std::pow(20.0 * 0.1 * kDeg, 2), 1e-12);
  EXPECT_NEAR(C(0, 1), 0.0, 1e-12);
  // Far range (beyond 70 m): 0.40 m along the beam.
  C = polarCovariance(100.0, 0.0, a);
  EXPECT_NEAR(C(0, 0), 0.40 * 0.40, 1e-12);
  // At 30° the azimuth σ is half way to the edge's 1°: 0.55°; the eigenvectors follow the beam.
  const double r = 50.0, az = 30.0 * kDeg;
  C = polarCovariance(r * std::cos(az), r * std::sin(az), a);
  const Eigen::Vector2d along(std::cos(az), std::sin(az)), across(-std::sin(az), std::cos(az));
  EXPECT_NEAR(along.dot(C * along), 0.10 * 0.10, 1e-12);
  EXPECT_NEAR(across.dot(C * across), std::pow(r * 0.55 * kDeg, 2), 1e-12);
  EXPECT_NEAR(along.dot(C * across), 0.0, 1e-12);
  // Beyond the edge azimuth (60°) it stays at the edge's 1°.
  const double edge = 80.0 * kDeg;
  C = polarCovariance(r * std::cos(edge), r * std::sin(edge), a);
  const Eigen::Vector2d side(-std::sin(edge), std::cos(edge));
  EXPECT_NEAR(side.dot(C * side), std::pow(r * 1.0 * kDeg, 2), 1e-12);
}

TEST(PointCovariance, CovariancesTurnWithTheMountingIntoTheVehicleFrame) {
  pcl::PointCloud<PointRadar> cloud;
  cloud.push_back(PointRadar(40.0f, 0.0f, 0.0f, 1.0f));  // straight ahead of the radar
  const double yaw = 90.0 * kDeg;                        // a radar looking left
  setPointCovariances(cloud, yaw, PointCovarianceModel::Polar, PolarAccuracy{});
  // Its beam points along +y of the vehicle: narrow in y, wide in x.
  EXPECT_NEAR(cloud[0].cov_yy, 0.10 * 0.10, 1e-6);
  EXPECT_NEAR(cloud[0].cov_xx, std::pow(40.0 * 0.1 * kDeg, 2), 1e-6);
  EXPECT_NEAR(cloud[0].cov_xy, 0.0, 1e-7);
}

TEST(PointCovariance, ReportedRmsIsUsedWhereTheFileHasIt) {
  pcl::PointCloud<PointRadar> cloud;
  PointRadar with(30.0f, 0.0f, 0.0f, 1.0f), without(30.0f, 0.0f, 0.0f, 1.0f);
  with.cov_xx = 0.25f;  // x_rms 0.5 m
  with.cov_yy = 0.04f;  // y_rms 0.2 m
  cloud.push_back(with);
  cloud.push_back(without);
  setPointCovariances(cloud, 0.0, PointCovarianceModel::ReportedRms, PolarAccuracy{});
  EXPECT_FLOAT_EQ(cloud[0].cov_xx, 0.25f);
  EXPECT_FLOAT_EQ(cloud[0].cov_yy, 0.04f);
  EXPECT_NEAR(cloud[1].cov_xx, 0.01, 1e-6) << "no rms: the polar model";
  EXPECT_EQ(parseEnum<PointCovarianceModel>("polar"), PointCovarianceModel::Polar);
  EXPECT_EQ(parseEnum<PointCovarianceModel>("rms"), PointCovarianceModel::ReportedRms);
  EXPECT_STREQ(toString(PointCovarianceModel::ReportedRms), "rms");
  EXPECT_THROW(parseEnum<PointCovarianceModel>("spec"), std::invalid_argument);
}
