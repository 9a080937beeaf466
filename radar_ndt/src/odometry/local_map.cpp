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
  return concatenateCycles(clouds_);
}

}  // namespace radar_ndt
