#pragma once
// radar_ndt::TopViewMap: scans drawn into one top-view image at their odometry poses, to see
// whether the aligned structure is sharp (a good trajectory) or doubled (a bad one). Each pixel
// keeps the strongest power any scan put there; the trajectory is drawn on top.

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include <pcl/point_cloud.h>

#include "radar_ndt/point_types.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

class TopViewMap {
 public:
  /// `resolution`: metres per pixel (> 0).
  explicit TopViewMap(double resolution = 0.25);

  /// Adds `cloud` (vehicle frame) at `pose` (the map frame), and the pose to the trajectory.
  void add(const pcl::PointCloud<PointRadar>& cloud, const Pose2& pose);

  /// Pixels any point fell in: fewer for the same scans means less doubled structure.
  std::size_t occupiedPixels() const { return cells_.size(); }
  double resolution() const { return resolution_; }

  /// Writes an RGB PNG (power in gray, the trajectory in red, north = +x up), cropped to the
  /// content plus a margin and scaled down if a side would exceed `max_side` pixels. Throws
  /// IoError when the file cannot be written, std::logic_error when the map is empty.
  void writePng(const std::string& path, int max_side = 4000) const;

 private:
  double resolution_;
  std::unordered_map<std::uint64_t, float> cells_;
  std::vector<Pose2> poses_;
};

}  // namespace radar_ndt
