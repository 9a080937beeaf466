// LocalMap: the last M cycles moved into each new frame by the estimated motion.
#include <gtest/gtest.h>

#include "radar_ndt/odometry/local_map.h"

using namespace radar_ndt;

namespace {
pcl::PointCloud<PointRadar> onePoint(float x, float y) {
  pcl::PointCloud<PointRadar> c;
  PointRadar p(x, y, 0.f);
  p.cov_xx = p.cov_yy = 0.01f;
  p.cov_xy = 0.f;
  c.push_back(p);
  return c;
}
}  // namespace

TEST(LocalMap, MovesKeptCyclesIntoTheNewFrameAndDropsTheOldest) {
  LocalMap map(2);
  EXPECT_EQ(map.capacity(), 2u);
  map.add(onePoint(10.f, 0.f));
  // The vehicle moves 1 m forward and turns 90° left: the point 10 m ahead is now 9 m to the right.
  map.advance(Pose2(1.0, 0.0, kPi / 2), Eigen::Matrix3d::Zero());
  map.add(onePoint(5.f, 0.f));
  auto cloud = map.cloud();
  ASSERT_EQ(cloud->size(), 2u);
  EXPECT_NEAR((*cloud)[0].x, 0.0, 1e-5);
  EXPECT_NEAR((*cloud)[0].y, -9.0, 1e-5);
  EXPECT_NEAR((*cloud)[1].x, 5.0, 1e-6);
  // The motion's uncertainty grows the moved points' covariance (yaw: 9 m lever arm).
  map.advance(Pose2(0.0, 0.0, 0.0), Eigen::Vector3d(0.0, 0.0, 1e-4).asDiagonal());
  cloud = map.cloud();
  EXPECT_NEAR((*cloud)[0].cov_xx, 0.01 + 81 * 1e-4, 1e-5);
  EXPECT_NEAR((*cloud)[1].cov_yy, 0.01 + 25 * 1e-4, 1e-5);
  map.add(onePoint(1.f, 1.f));
  EXPECT_EQ(map.cycles(), 2u);
  EXPECT_EQ(map.cloud()->size(), 2u);
  EXPECT_NEAR((*map.cloud())[0].x, 5.0, 1e-5) << "the first cycle was dropped";
  map.clear();
  EXPECT_EQ(map.cloud()->size(), 0u);
  EXPECT_EQ(LocalMap(0).capacity(), 1u);
}
