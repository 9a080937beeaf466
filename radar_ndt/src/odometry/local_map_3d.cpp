#include "radar_ndt/odometry/local_map_3d.h"

#include <algorithm>
#include <cmath>

#include "radar_ndt/registration/detail/point_fields.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

void LocalMap3DOptions::validate() const {
  checkFields(*this, "LocalMap3DOptions");
}

LocalMap3D::LocalMap3D(const LocalMap3DOptions& o) : options_(o) {
  options_.validate();
}

bool LocalMap3D::wantsKeyframe(const Eigen::Isometry3d& pose, std::uint16_t radar) const {
  const auto last = last_.find(radar);
  if (last == last_.end()) return true;
  const Eigen::Isometry3d d = last->second.inverse() * pose;
  const double angle = Eigen::AngleAxisd(d.linear()).angle() * 180.0 / kPi;
  return d.translation().norm() >= options_.distance || angle >= options_.angle_deg;
}

void LocalMap3D::add(const pcl::PointCloud<PointRadar4D>& scan, const Eigen::Isometry3d& pose, std::uint16_t radar) {
  clouds_.push_back(transformRadar4D(scan, pose));
  radars_.push_back(radar);
  if (std::count(radars_.begin(), radars_.end(), radar) > options_.scans) {  // that radar's oldest goes
    const std::size_t i = std::find(radars_.begin(), radars_.end(), radar) - radars_.begin();
    clouds_.erase(clouds_.begin() + static_cast<std::ptrdiff_t>(i));
    radars_.erase(radars_.begin() + static_cast<std::ptrdiff_t>(i));
  }
  last_[radar] = pose;
  cache_.reset();
}

pcl::PointCloud<PointRadar4D>::ConstPtr LocalMap3D::cloud() const {
  if (!cache_) {
    cache_.reset(new pcl::PointCloud<PointRadar4D>);
    for (const auto& c : clouds_) *cache_ += c;
  }
  return cache_;
}

pcl::PointCloud<PointRadar4D> transformRadar4D(const pcl::PointCloud<PointRadar4D>& cloud, const Eigen::Isometry3d& T) {
  pcl::PointCloud<PointRadar4D> out = cloud;
  const Eigen::Matrix3d R = T.linear();
  for (PointRadar4D& p : out) {
    const Eigen::Vector3d q = T * Eigen::Vector3d(p.x, p.y, p.z);
    p.x = static_cast<float>(q.x());
    p.y = static_cast<float>(q.y());
    p.z = static_cast<float>(q.z());
    detail::rotateCovariance3D(p, R);
  }
  return out;
}

}  // namespace radar_ndt
