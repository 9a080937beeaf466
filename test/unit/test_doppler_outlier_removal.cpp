// DopplerOutlierRemoval: a PCL filter that keeps the detections whose Doppler agrees with the
// ego-velocity.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "radar_ndt/frontend/doppler_outlier_removal.h"
#include "radar_ndt/frontend/ego_velocity.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

namespace {

std::vector<SensorMounting> nuScenesLikeMountings() {
  return {{3.41, 0.0, 0.0, true}, {2.42, 0.8, kPi / 2, true}, {2.42, -0.8, -kPi / 2, true}, {-0.56, 0.63, kPi, true},
          {-0.56, -0.62, -kPi, true}};
}

/// Stationary detections around the car seen with velocity v, plus `movers` detections with a
/// Doppler 3 m/s off; Gaussian Doppler noise σ.
pcl::PointCloud<PointRadar> makeCycle(const Eigen::Vector3d& v, int movers, double sigma, std::uint32_t seed) {
  const auto mounts = nuScenesLikeMountings();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> az(-1.0, 1.0), range(5.0, 80.0);
  std::normal_distribution<double> noise(0.0, sigma);
  pcl::PointCloud<PointRadar> cloud;
  for (std::uint16_t s = 0; s < mounts.size(); ++s) {
    for (int i = 0; i < 40; ++i) {
      const double a = mounts[s].yaw + az(rng), r = range(rng);
      PointRadar p(static_cast<float>(mounts[s].x + r * std::cos(a)), static_cast<float>(mounts[s].y + r * std::sin(a)), 0.f);
      p.sensor_id = s;
      p.doppler = static_cast<float>(predictedDoppler(mounts[s], p.x, p.y, v) + noise(rng) + (i < movers ? 3.0 : 0.0));
      cloud.push_back(p);
    }
  }
  return cloud;
}

}  // namespace

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
  for (const auto& p : removed) EXPECT_GT(std::abs(p.doppler - predictedDoppler(nuScenesLikeMountings()[p.sensor_id], p.x, p.y, v)), 2.0);
  // Through the base class, as PCL users compose filters.
  pcl::Filter<PointRadar>::Ptr base = pcl::make_shared<DopplerOutlierRemoval<PointRadar>>(f);
  pcl::PointCloud<PointRadar> again;
  base->filter(again);
  EXPECT_EQ(again.size(), 50u);
}
