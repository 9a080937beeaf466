// detail/source_points.h: the matching weights of eq. (2) as numbers, the points left out, and the
// voxel merge (weighted centroids in first-seen order, the same through its dense table or hash).
#include <gtest/gtest.h>

#include "radar_ndt/registration/detail/source_points.h"
#include "registration_support.h"

using namespace radar_ndt;
using radar_ndt::test::pointWith;

TEST(SourcePoints, WeightsAreEquationTwo) {
  // Eq. (2), the numbers themselves: w = max(p - s, 0) exp(-1/2 (sigma_x + sigma_y)), sigma_x and
  // sigma_y the point's standard deviations (not variances); a point below the shift is left out.
  pcl::PointCloud<PointRadar> source;
  source.push_back(pointWith(1.0f, 2.0f, 0.8f, 0.04f, 0.0f, 0.09f));  // sigma 0.2 and 0.3 m
  source.push_back(pointWith(5.0f, -1.0f, 0.5f, 0.25f, 0.1f, 1.0f));  // sigma 0.5 and 1 m
  source.push_back(pointWith(3.0f, 3.0f, 0.2f, 0.01f, 0.0f, 0.01f));  // below s
  const pcl::Indices all{0, 1, 2};
  std::vector<detail::WeightedPoint2D> out;
  detail::weightSourcePoints(source, all, 0.3, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(out[0].w, (0.8f - 0.3) * std::exp(-0.5 * (0.2 + 0.3)), 1e-5);
  EXPECT_NEAR(out[1].w, (0.5f - 0.3) * std::exp(-0.5 * (0.5 + 1.0)), 1e-5);
  EXPECT_EQ(out[1].x, 5.0);
}

TEST(SourcePoints, UnusablePointsAreLeftOut) {
  pcl::PointCloud<PointRadar> source;
  source.push_back(pointWith(std::nanf(""), 1.0f, 0.9f, 0.01f, 0.0f, 0.01f));  // NaN position
  source.push_back(pointWith(1.0f, 1.0f, 0.9f, -0.01f, 0.0f, 0.01f));          // negative variance
  source.push_back(pointWith(1.0f, 1.0f, 0.9f, 0.01f, 0.0f, INFINITY));        // infinite variance
  source.push_back(pointWith(1.0f, 1.0f, std::nanf(""), 0.01f, 0.0f, 0.01f));  // NaN power
  source.push_back(pointWith(2.0f, 3.0f, 0.9f, 0.0f, 0.0f, 0.0f));             // kept
  const pcl::Indices all{0, 1, 2, 3, 4};
  std::vector<detail::WeightedPoint2D> out;
  detail::weightSourcePoints(source, all, 0.0, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].x, 2.0);
  EXPECT_NEAR(out[0].w, 0.9, 1e-6);
  // Only the indices given are read.
  detail::weightSourcePoints(source, pcl::Indices{0, 1}, 0.0, out);
  EXPECT_TRUE(out.empty());
}

TEST(SourcePoints, VoxelMergeGivesWeightedCentroidsInFirstSeenOrder) {
  std::vector<detail::WeightedPoint2D> points{{0.1, 0.1, 1.0}, {5.1, 5.1, 2.0}, {0.3, 0.1, 3.0}, {5.2, 5.0, 2.0}};
  detail::SourceVoxelScratch scratch;
  detail::mergeSourceVoxels(0.5, points, scratch);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_NEAR(points[0].x, (0.1 * 1 + 0.3 * 3) / 4, 1e-12);
  EXPECT_NEAR(points[0].y, 0.1, 1e-12);
  EXPECT_EQ(points[0].w, 4.0);
  EXPECT_NEAR(points[1].x, 5.15, 1e-12);
  EXPECT_NEAR(points[1].y, 5.05, 1e-12);
  EXPECT_EQ(points[1].w, 4.0);
  // A point beyond any sensible extent stretches the keys' box past the dense table: the hash
  // path merges the rest the same, and the far point is dropped (it cannot be keyed).
  std::vector<detail::WeightedPoint2D> stretched{{0.1, 0.1, 1.0}, {5.1, 5.1, 2.0},  {0.3, 0.1, 3.0},
                                                 {5.2, 5.0, 2.0}, {4e8, -4e8, 1.0}, {1e12, 0.0, 1.0}};
  detail::mergeSourceVoxels(0.5, stretched, scratch);
  ASSERT_EQ(stretched.size(), 3u);
  EXPECT_EQ(stretched[0].x, points[0].x);
  EXPECT_EQ(stretched[1].x, points[1].x);
  EXPECT_EQ(stretched[2].x, 4e8);
  // A voxel size of 0 leaves the points as they are.
  std::vector<detail::WeightedPoint2D> same{{0.1, 0.1, 1.0}, {0.2, 0.1, 1.0}};
  detail::mergeSourceVoxels(0.0, same, scratch);
  EXPECT_EQ(same.size(), 2u);
}
