// detail/lazy_kdtree.h: the target kd-tree is built when first searched, not when set, and then
// answers as PCL's own.
#include <gtest/gtest.h>

#include <pcl/point_types.h>

#include "radar_ndt/registration/detail/lazy_kdtree.h"

using namespace radar_ndt;

namespace {
/// Tells whether PCL's tree under the lazy one has been given its cloud, i.e. built.
struct Exposed : detail::LazyKdTree<pcl::PointXYZ> {
  bool built() const { return this->tree_->getInputCloud() != nullptr; }
};
}  // namespace

TEST(LazyKdTree, AnswersAsPclsTreeAfterBuildingOnTheFirstSearch) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  for (int i = 0; i < 100; ++i) cloud->push_back(pcl::PointXYZ(0.1f * i, 0.05f * (i % 7), 0.f));
  Exposed lazy;
  pcl::search::KdTree<pcl::PointXYZ> eager;
  lazy.setInputCloud(cloud);
  eager.setInputCloud(cloud);
  EXPECT_EQ(lazy.getInputCloud(), cloud) << "the cloud is kept when set";
  EXPECT_FALSE(lazy.built()) << "setting the cloud builds nothing";
  const pcl::PointXYZ query(3.33f, 0.1f, 0.f);
  pcl::Indices a, b;
  std::vector<float> da, db;
  ASSERT_EQ(lazy.nearestKSearch(query, 5, a, da), 5);
  EXPECT_TRUE(lazy.built());
  eager.nearestKSearch(query, 5, b, db);
  EXPECT_EQ(a, b);
  EXPECT_EQ(da, db);
  ASSERT_GT(lazy.radiusSearch(query, 0.5, a, da), 0);
  eager.radiusSearch(query, 0.5, b, db);
  EXPECT_EQ(a, b);
  // A new cloud replaces the tree at the next search.
  pcl::PointCloud<pcl::PointXYZ>::Ptr other(new pcl::PointCloud<pcl::PointXYZ>);
  other->push_back(pcl::PointXYZ(100.f, 100.f, 0.f));
  lazy.setInputCloud(other);
  ASSERT_EQ(lazy.nearestKSearch(query, 1, a, da), 1);
  EXPECT_EQ(a[0], 0);
  EXPECT_GT(da[0], 9000.f);
}
