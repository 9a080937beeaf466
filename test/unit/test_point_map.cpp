#include <gtest/gtest.h>

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include "radar_ndt/evaluation/point_map.h"

using namespace radar_ndt;

// The map holds each cloud at its pose (x, y rotated by the yaw, then moved), one point a voxel,
// and its file is read by PCL itself.
TEST(PointMap, PlacesCloudsAtTheirPosesOnePointAVoxelAndPclReadsIt) {
  pcl::PointCloud<PointRadar> cloud;
  cloud.push_back(PointRadar(1.0f, 0.0f, 0.5f));
  cloud.push_back(PointRadar(1.05f, -0.03f, 0.5f));  // the same 0.2 m voxel once placed
  cloud.push_back(PointRadar(0.0f, 2.0f, 0.0f));
  PointMap map(0.2);
  map.add(cloud, Pose2(10.1, -3.1, kPi / 2));
  ASSERT_EQ(map.cloud().size(), 2u);
  EXPECT_NEAR(map.cloud()[0].x, 10.1, 1e-5);  // (1, 0) turned a quarter: (0, 1)
  EXPECT_NEAR(map.cloud()[0].y, -2.1, 1e-5);
  EXPECT_NEAR(map.cloud()[0].z, 0.5, 1e-6);
  EXPECT_NEAR(map.cloud()[1].x, 8.1, 1e-5);  // (0, 2): (−2, 0)
  EXPECT_NEAR(map.cloud()[1].y, -3.1, 1e-5);
  map.add(cloud, Pose2(10.1, -3.1, kPi / 2));  // the same places again: nothing new
  EXPECT_EQ(map.cloud().size(), 2u);
  PointMap every(0.0);
  every.add(cloud, Pose2(0, 0, 0));
  EXPECT_EQ(every.cloud().size(), 3u);
  const std::string path = ::testing::TempDir() + "radar_ndt_point_map.pcd";
  map.write(path);
  pcl::PointCloud<pcl::PointXYZ> read;
  ASSERT_EQ(pcl::io::loadPCDFile(path, read), 0);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_NEAR(read[1].x, 8.1, 1e-5);
  EXPECT_THROW(PointMap(-1.0), std::invalid_argument);
}
