#pragma once
// What the scanning odometry matches against (beyond the paper): the keyframe scan at its
// reference time, the copy of it as given that compensation rounds move again, whether it was
// compensated, and what the matcher holds of it. One object owns that state, so the target model
// is built once per keyframe and again only when a compensation round swapped in another copy.

#include <pcl/point_cloud.h>

#include "radar_ndt/odometry/matcher.h"
#include "radar_ndt/point_types.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

class KeyframeTarget {
 public:
  using Cloud = pcl::PointCloud<PointRadar>;

  /// The first scan: its velocity is unknown, so it is kept as given with its time offsets zeroed
  /// (short against any later correction), until compensateFirst().
  void resetFirst(const Cloud& scan);
  /// A new keyframe: `scan` moved to its reference time with `velocity` (body frame, m/s and
  /// rad/s), or as given when `velocity` is null (compensation off).
  void reset(const Cloud& scan, const Eigen::Vector3d* velocity);
  /// The first scan compensated with the first velocity there is; nothing once compensated.
  void compensateFirst(const Eigen::Vector3d& velocity);

  /// The keyframe at its reference time (null before the first scan).
  const Cloud::Ptr& cloud() const { return cloud_; }
  std::size_t size() const { return cloud_ ? cloud_->size() : 0; }
  /// Whether the keyframe was moved to its reference time (every keyframe but an uncompensated first).
  bool compensated() const { return compensated_; }

  /// Makes the keyframe as it is the matcher's target, unless the matcher holds it already.
  void giveTo(RadarRegistration& matcher);
  /// Gives the matcher the keyframe's scan as given, moved with `velocity` instead (a compensation
  /// round's target); the keyframe itself is unchanged.
  void giveRecompensated(RadarRegistration& matcher, const Eigen::Vector3d& velocity);
  /// After giveRecompensated(): the keyframe as it is the matcher's target again.
  void restore(RadarRegistration& matcher);

 private:
  Cloud::Ptr cloud_;          ///< the keyframe at its reference time
  Cloud::ConstPtr raw_;       ///< the keyframe's scan as given, to move again
  bool compensated_ = false;  ///< cloud_ was moved to its reference time
  bool held_ = false;         ///< the matcher's target (and model) is cloud_ as it is
  bool replaced_ = false;     ///< the matcher holds a re-compensated copy instead
};

}  // namespace radar_ndt
