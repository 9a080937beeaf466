#include "radar_ndt/odometry/local_map.h"

#include <algorithm>

#include "radar_ndt/frontend/probabilistic_submap.h"

namespace radar_ndt {

LocalMap::LocalMap(std::size_t cycles) : capacity_(std::max<std::size_t>(1, cycles)) {}

void LocalMap::advance(const Pose2& motion, const Eigen::Matrix3d& motion_covariance) {
  for (auto& c : clouds_) transformWithUncertainty(c, motion, motion_covariance);
}

void LocalMap::add(const pcl::PointCloud<PointRadar>& cycle) {
  clouds_.push_back(cycle);
  while (clouds_.size() > capacity_) clouds_.pop_front();
}

pcl::PointCloud<PointRadar>::Ptr LocalMap::cloud() const {
  pcl::PointCloud<PointRadar>::Ptr out(new pcl::PointCloud<PointRadar>);
  std::size_t n = 0;
  for (const auto& c : clouds_) n += c.size();
  out->reserve(n);
  for (const auto& c : clouds_) out->insert(out->end(), c.begin(), c.end());
  out->width = static_cast<std::uint32_t>(out->size());
  out->height = 1;
  return out;
}

}  // namespace radar_ndt
