#include "radar_ndt/odometry/keyframe_target.h"

#include "radar_ndt/odometry/motion_compensation.h"

namespace radar_ndt {

void KeyframeTarget::resetFirst(const Cloud& scan) {
  raw_.reset(new Cloud(scan));  // a copy: the caller's cloud is not kept
  compensated_ = false;
  cloud_.reset(new Cloud(scan));
  held_ = false;
  for (auto& p : *cloud_) p.time_offset = 0.f;
}

void KeyframeTarget::reset(const Cloud& scan, const Eigen::Vector3d* velocity) {
  raw_.reset(new Cloud(scan));
  cloud_.reset(new Cloud);
  held_ = false;
  if (velocity)
    compensateMotion(scan, *velocity, *cloud_);
  else
    *cloud_ = scan;
  compensated_ = true;
}

void KeyframeTarget::compensateFirst(const Eigen::Vector3d& velocity) {
  if (compensated_ || !raw_) return;
  cloud_.reset(new Cloud);
  held_ = false;
  compensateMotion(*raw_, velocity, *cloud_);
  compensated_ = true;
}

void KeyframeTarget::giveTo(RadarRegistration& matcher) {
  // Once per keyframe, not once per scan: while the keyframe is kept the matcher still holds it.
  if (!held_ || replaced_) matcher.setInputTarget(cloud_);
  held_ = true;
  replaced_ = false;
}

void KeyframeTarget::giveRecompensated(RadarRegistration& matcher, const Eigen::Vector3d& velocity) {
  if (!raw_) return;
  Cloud::Ptr moved(new Cloud);
  compensateMotion(*raw_, velocity, *moved);
  matcher.setInputTarget(moved);
  replaced_ = true;
}

void KeyframeTarget::restore(RadarRegistration& matcher) {
  if (!replaced_) return;
  matcher.setInputTarget(cloud_);
  replaced_ = false;
}

}  // namespace radar_ndt
