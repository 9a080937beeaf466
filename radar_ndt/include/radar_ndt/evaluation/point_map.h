#pragma once
// A map of a run's points in the world frame (the first pose's frame), for `--map-out map.pcd` and
// the ROS node's users: each cloud placed at its estimated pose, at most one point a voxel (the
// first that falls in it), written as a PointRadar PCD that PCL reads (x y z power rcs ...).

#include <cstdint>
#include <string>
#include <unordered_set>

#include <pcl/point_cloud.h>

#include "radar_ndt/point_types.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

class PointMap {
 public:
  /// `voxel` (m) > 0: one point a voxel of that side; 0: every point.
  explicit PointMap(double voxel = 0.2);
  /// Adds `cloud` (in the vehicle frame at `pose`) in the world frame.
  void add(const pcl::PointCloud<PointRadar>& cloud, const Pose2& pose);
  const pcl::PointCloud<PointRadar>& cloud() const { return cloud_; }
  /// Writes the map (binary PCD, atomically). Throws IoError naming the file.
  void write(const std::string& path) const;

 private:
  double voxel_;
  pcl::PointCloud<PointRadar> cloud_;
  std::unordered_set<std::uint64_t> occupied_;
};

}  // namespace radar_ndt
