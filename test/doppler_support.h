#pragma once
// Constructed automotive detections for the Doppler tests: nuScenes-like radar mountings and a
// cycle of stationary detections (and some movers) seen with a known ego-velocity.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <pcl/point_cloud.h>

#include "radar_ndt/frontend/ego_velocity.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace test {
inline std::vector<SensorMounting> nuScenesLikeMountings() {
  return {{3.41, 0.0, 0.0, true},
          {2.42, 0.8, kPi / 2, true},
          {2.42, -0.8, -kPi / 2, true},
          {-0.56, 0.63, kPi, true},
          {-0.56, -0.62, -kPi, true}};
}

/// Stationary detections around the car seen with velocity v, plus `movers` detections with a
/// Doppler 3 m/s off; Gaussian Doppler noise σ.
inline pcl::PointCloud<PointRadar> makeCycle(const Eigen::Vector3d& v, int movers, double sigma, std::uint32_t seed) {
  const auto mounts = nuScenesLikeMountings();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> az(-1.0, 1.0), range(5.0, 80.0);
  std::normal_distribution<double> noise(0.0, sigma);
  pcl::PointCloud<PointRadar> cloud;
  for (std::uint16_t s = 0; s < mounts.size(); ++s) {
    for (int i = 0; i < 40; ++i) {
      const double a = mounts[s].yaw + az(rng), r = range(rng);
      PointRadar p(static_cast<float>(mounts[s].x + r * std::cos(a)), static_cast<float>(mounts[s].y + r * std::sin(a)),
                   0.f);
      p.sensor_id = s;
      p.doppler = static_cast<float>(predictedDoppler(mounts[s], p.x, p.y, v) + noise(rng) + (i < movers ? 3.0 : 0.0));
      cloud.push_back(p);
    }
  }
  return cloud;
}

}  // namespace test
}  // namespace radar_ndt
