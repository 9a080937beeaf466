// mergeVoxels: points per square voxel merged into one, in order of each voxel's first point.
#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

#include "radar_ndt/frontend/voxel_merge.h"

using namespace radar_ndt;

TEST(VoxelMerge, AveragesPositionTimeAndCovarianceKeepsTheStrongestPower) {
  pcl::PointCloud<PointRadar> in, out;
  PointRadar a(0.05f, 0.05f, 0.f, 0.4f), b(0.15f, 0.20f, 0.f, 0.9f), c(1.1f, -0.1f, 0.f, 0.5f);
  a.time_offset = 0.1f;
  b.time_offset = 0.2f;
  a.cov_xx = 0.01f;
  b.cov_xx = 0.03f;
  in.push_back(c);                                                              // voxel (4, -1) at 0.25 m, first
  in.push_back(a);                                                              // voxel (0, 0)
  in.push_back(b);                                                              // voxel (0, 0)
  in.push_back(PointRadar(std::numeric_limits<float>::quiet_NaN(), 0.f, 0.f));  // dropped
  mergeVoxels(in, 0.25, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_FLOAT_EQ(out[0].x, 1.1f);  // first-appearance order
  EXPECT_FLOAT_EQ(out[1].x, 0.10f);
  EXPECT_FLOAT_EQ(out[1].y, 0.125f);
  EXPECT_FLOAT_EQ(out[1].time_offset, 0.15f);
  EXPECT_FLOAT_EQ(out[1].cov_xx, 0.02f);
  EXPECT_FLOAT_EQ(out[1].power, 0.9f);
  EXPECT_EQ(out.width, 2u);
  EXPECT_TRUE(out.is_dense);
}

TEST(VoxelMerge, NegativeCoordinatesFloorIntoTheirOwnVoxels) {
  pcl::PointCloud<PointRadar> in, out;
  in.push_back(PointRadar(-0.1f, 0.f, 0.f));
  in.push_back(PointRadar(0.1f, 0.f, 0.f));  // the other side of 0: another voxel
  in.push_back(PointRadar(-0.3f, 0.1f, 0.f));
  mergeVoxels(in, 0.25, out);
  ASSERT_EQ(out.size(), 3u);
  mergeVoxels(in, 1.0, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_FLOAT_EQ(out[0].x, -0.2f);
  EXPECT_FLOAT_EQ(out[0].y, 0.05f);
}

TEST(VoxelMerge, ASizeThatIsNotPositiveIsAnError) {
  pcl::PointCloud<PointRadar> in, out;
  EXPECT_THROW(mergeVoxels(in, 0.0, out), std::invalid_argument);
  EXPECT_THROW(mergeVoxels(in, -1.0, out), std::invalid_argument);
}
