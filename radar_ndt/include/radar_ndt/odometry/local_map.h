#pragma once
// A local map of the last M radar cycles in the newest cycle's frame, each placed by the motions
// the odometry estimated (not by the Doppler integral, as the paper's probabilistic submap places
// its cycles). A new cycle matched against it shares no points with it, so the match measures the
// cycle's pose against geometry placed independently of this cycle's Doppler motion, and its
// errors do not accumulate from cycle to cycle (scan-to-map, as KISS-ICP's local map). Point
// covariances grow with each motion's uncertainty, as in the probabilistic submap (Sec. III-B).

#include <deque>

#include <Eigen/Core>
#include <pcl/point_cloud.h>

#include "radar_ndt/point_types.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

class LocalMap {
 public:
  explicit LocalMap(std::size_t cycles = 10);

  /// Moves the kept cycles into the next frame: `motion` is the next frame's pose in the current
  /// one, `motion_covariance` its covariance (transformWithUncertainty).
  void advance(const Pose2& motion, const Eigen::Matrix3d& motion_covariance);
  /// Adds a cycle given in the current frame; the oldest is dropped beyond M cycles.
  void add(const pcl::PointCloud<PointRadar>& cycle);
  /// All kept cycles in the current frame, oldest first.
  pcl::PointCloud<PointRadar>::Ptr cloud() const;

  std::size_t cycles() const { return clouds_.size(); }
  std::size_t capacity() const { return capacity_; }
  void clear() { clouds_.clear(); }

 private:
  std::size_t capacity_;
  std::deque<pcl::PointCloud<PointRadar>> clouds_;
};

}  // namespace radar_ndt
