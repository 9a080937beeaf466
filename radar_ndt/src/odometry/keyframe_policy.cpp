#include "radar_ndt/odometry/keyframe_policy.h"

#include <cmath>
#include <stdexcept>

namespace radar_ndt {

void KeyframeOptions::validate() const {
  checkFields(*this, "KeyframeOptions");
}

bool KeyframePolicy::replaceAfter(bool matched, const Pose2& pose, bool keyframe_usable) {
  consecutive_failures_ = matched ? 0 : consecutive_failures_ + 1;
  if (!matched) return consecutive_failures_ >= 2 || !keyframe_usable;
  const Pose2 from_keyframe = between(pose_, pose);
  return !(options_.distance > 0) || from_keyframe.head<2>().norm() >= options_.distance ||
         std::abs(from_keyframe.z()) >= options_.rotation;
}

}  // namespace radar_ndt
