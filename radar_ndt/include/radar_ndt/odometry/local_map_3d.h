#pragma once
// The 6-DoF odometry's local map: the last M keyframe scans in the odometry (world) frame, each
// placed by its fused pose, each point's covariance turned with it. A single 4D scan is too sparse
// to match against the next (a TI scan holds tens of detections), so each scan is matched against
// this map (scan-to-map, as KISS-ICP's local map and the planar LocalMap). A scan joins it only
// after the body moved `distance` or turned `angle` since the last one joined, so that a rig
// standing still keeps matching against the same geometry and does not drift. With several radars
// a rig, each radar's scans are keyframes of their own (`radar`): M of them each, each joining after
// the body moved since that radar's last one, so that one radar's keyframes never keep another's
// view out of the map.

#include <cstdint>
#include <deque>
#include <map>

#include <Eigen/Geometry>
#include <pcl/point_cloud.h>

#include "radar_ndt/fields.h"
#include "radar_ndt/point_types.h"

namespace radar_ndt {

struct LocalMap3DOptions {
  int scans = 20;          ///< keyframe scans kept (of each radar)
  double distance = 0.5;   ///< m the body moves before the next keyframe
  double angle_deg = 3.0;  ///< deg it turns before the next keyframe
  void validate() const;
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void LocalMap3DOptions::fields(Visit&& visit) {
  using S = LocalMap3DOptions;
  visit(&S::scans, Field("scans", "keyframe scans in the local map (of each radar)").atLeast(1));
  visit(&S::distance, Field("distance", "the body's travel before the next keyframe").unit("m").atLeast(0));
  visit(&S::angle_deg, Field("angle_deg", "the body's turn before the next keyframe").unit("deg").atLeast(0));
}

class LocalMap3D {
 public:
  /// Validates `o` (std::invalid_argument).
  explicit LocalMap3D(const LocalMap3DOptions& o = {});
  /// Whether a scan of `radar` at `pose` (body to world) would join: its first always, then after
  /// the keyframe distance or angle from that radar's last keyframe.
  bool wantsKeyframe(const Eigen::Isometry3d& pose, std::uint16_t radar = 0) const;
  /// Adds `scan` (body frame, with covariances) of `radar` placed at `pose`; that radar's oldest
  /// beyond M is dropped.
  void add(const pcl::PointCloud<PointRadar4D>& scan, const Eigen::Isometry3d& pose, std::uint16_t radar = 0);
  /// All kept scans in the world frame, oldest first (the same pointer until the next add).
  pcl::PointCloud<PointRadar4D>::ConstPtr cloud() const;
  std::size_t size() const { return clouds_.size(); }
  bool empty() const { return clouds_.empty(); }

 private:
  LocalMap3DOptions options_;
  std::deque<pcl::PointCloud<PointRadar4D>> clouds_;
  std::deque<std::uint16_t> radars_;                 ///< each kept scan's radar
  std::map<std::uint16_t, Eigen::Isometry3d> last_;  ///< each radar's last keyframe pose
  mutable pcl::PointCloud<PointRadar4D>::Ptr cache_;
};

/// `cloud` moved by `T`: positions and each point's covariance (R C Rᵀ).
pcl::PointCloud<PointRadar4D> transformRadar4D(const pcl::PointCloud<PointRadar4D>& cloud, const Eigen::Isometry3d& T);

}  // namespace radar_ndt
