// DopplerOutlierRemoval: a PCL filter that keeps the detections whose Doppler agrees with the
// ego-velocity.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "radar_ndt/frontend/doppler_outlier_removal.h"
#include "radar_ndt/frontend/ego_velocity.h"
#include "radar_ndt/se2.h"

#include "doppler_support.h"

using namespace radar_ndt;

using test::makeCycle;
using test::nuScenesLikeMountings;

TEST(DopplerOutlierRemoval, IsAPclFilterWithNegative) {
  const Eigen::Vector3d v(6.0, 0.0, -0.1);
  const auto cloud = makeCycle(v, 10, 0.03, 5).makeShared();
  DopplerOutlierRemoval<PointRadar> f;
  f.setInputCloud(cloud);
  f.setEgoVelocity(v);
  f.setMountings(nuScenesLikeMountings());
  pcl::PointCloud<PointRadar> kept, removed;
  f.filter(kept);
  f.setNegative(true);
  f.filter(removed);
  EXPECT_EQ(kept.size(), 150u);
  EXPECT_EQ(removed.size(), 50u);
  for (const auto& p : removed)
    EXPECT_GT(std::abs(p.doppler - predictedDoppler(nuScenesLikeMountings()[p.sensor_id], p.x, p.y, v)), 2.0);
  // Through the base class, as PCL users compose filters.
  pcl::Filter<PointRadar>::Ptr base = pcl::make_shared<DopplerOutlierRemoval<PointRadar>>(f);
  pcl::PointCloud<PointRadar> again;
  base->filter(again);
  EXPECT_EQ(again.size(), 50u);
}

TEST(DopplerOutlierRemoval, ADetectionWithoutAUsableDopplerIsKept) {
  // A detection whose Doppler the reader left unused (NaN: RadarPointFields::keep_doppler) cannot
  // be told moving: it is kept, and the ego-velocity fit does not see it.
  const Eigen::Vector3d v(6.0, 0.0, -0.1);
  auto cloud = makeCycle(v, 10, 0.03, 5);
  for (std::size_t i = 0; i < cloud.size(); i += 4) cloud[i].doppler = std::numeric_limits<float>::quiet_NaN();
  DopplerOutlierRemoval<PointRadar> f;
  f.setInputCloud(cloud.makeShared());
  f.setEgoVelocity(v);
  f.setMountings(nuScenesLikeMountings());
  pcl::Indices kept;
  f.filter(kept);
  std::size_t unusable_kept = 0;
  for (const auto i : kept) unusable_kept += std::isnan(cloud[i].doppler) ? 1 : 0;
  EXPECT_EQ(unusable_kept, (cloud.size() + 3) / 4);
  const EgoVelocity fit = EgoVelocityEstimator(EgoVelocityOptions{}).estimate(cloud, nuScenesLikeMountings());
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.velocity.x(), v.x(), 0.1);
}
