#pragma once
// Keyframes (beyond the paper): a scan is matched to the last keyframe, not to the scan before
// it, so matching errors add up per keyframe rather than per scan.

#include <cstdint>

#include "radar_ndt/fields.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

struct KeyframeOptions {
  /// A matched scan this far (m) or turned this much (rad) from the keyframe replaces it. 0: every
  /// scan is the next one's target (scan to scan, as the paper).
  double distance = 8.0;
  double rotation = 0.1;
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void KeyframeOptions::fields(Visit&& visit) {
  using S = KeyframeOptions;
  visit(&S::distance, Field("distance",
                            "match to a keyframe replaced after this distance (or rotation, or a failed "
                            "match); 0: scan to scan as the paper")
                          .unit("m")
                          .atLeast(0)
                          .orInfinite()
                          .cli("keyframe-distance"));
  visit(&S::rotation, Field("rotation", "... or after this rotation").unit("rad").atLeast(0).orInfinite());
}

/// Which scan the next one is matched against: the keyframe is replaced by a matched scan far
/// enough from it, or after two failed matches in a row (one failed scan is never made the target:
/// it may be corrupt or all noise; a second failure means the keyframe itself no longer fits, e.g.
/// the view changed), or when it has too few points to be matched against.
class KeyframePolicy {
 public:
  explicit KeyframePolicy(const KeyframeOptions& options = {}) : options_(options) {}

  /// Makes the scan at `stamp_us` with `pose` the keyframe.
  void reset(const Pose2& pose, std::int64_t stamp_us) {
    pose_ = pose;
    stamp_us_ = stamp_us;
  }
  const Pose2& pose() const { return pose_; }
  std::int64_t stamp() const { return stamp_us_; }

  /// After a step at `pose`: whether that scan replaces the keyframe. `matched` says whether the
  /// step's match was accepted; `keyframe_usable` whether the keyframe has enough points.
  bool replaceAfter(bool matched, const Pose2& pose, bool keyframe_usable);

 private:
  KeyframeOptions options_;
  Pose2 pose_ = Pose2::Zero();
  std::int64_t stamp_us_ = 0;
  int consecutive_failures_ = 0;
};

}  // namespace radar_ndt
