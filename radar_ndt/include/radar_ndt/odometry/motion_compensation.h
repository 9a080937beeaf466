#pragma once
// Motion-distortion compensation (beyond the paper): a scanning radar's sweep takes a quarter of
// a second, so each point is moved from the vehicle pose at its azimuth's time to the pose at the
// scan's reference time.

#include <string>

#include <pcl/point_cloud.h>

#include "radar_ndt/fields.h"
#include "radar_ndt/point_types.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

/// How the source scan's sweep is de-skewed.
enum class CompensationMode {
  /// Moved to its reference time with the velocity of the step before it, then matched; rounds
  /// re-compensate source and target with the velocity the match found.
  Rounds,
  /// Inside the match (ours only): WeightedNDT2D::setSourceSweep places each source point by the
  /// motion being estimated at the point's time, so motion and de-skew are one unknown. The target
  /// is compensated as in Rounds, rounds re-compensating it with the velocity the match found.
  Joint,
};
template <>
struct EnumNames<CompensationMode> {
  static constexpr const char* what = "compensation mode";
  static constexpr EnumName<CompensationMode> names[] = {
      {CompensationMode::Rounds, "rounds", "with the velocity of the step before, re-estimated between matches"},
      {CompensationMode::Joint, "joint", "inside the match, by the motion being estimated (pw-ndt only)"}};
};

struct MotionCompensationOptions {
  bool enabled = true;
  CompensationMode mode = CompensationMode::Rounds;
  int max_rounds = 2;  ///< matches per attempt at most (the velocity re-estimated between them)
  /// m/s (yaw rate: × 10 m): another round only when the match moved the velocity by more. A
  /// single match's velocity noise is about 0.1 m/s; re-matching within it only chases noise.
  double tolerance = 0.25;
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void MotionCompensationOptions::fields(Visit&& visit) {
  using S = MotionCompensationOptions;
  visit(&S::enabled,
        Field("enabled", "move the points to the scan's reference time")
            .offSwitch("no-motion-compensation", "do not move points to the scan's reference time (ablation)"));
  visit(&S::mode, Field("mode", "how the source's sweep is de-skewed").cli("compensation"));
  visit(&S::max_rounds,
        Field("max_rounds", "matches per scan at most, the velocity of the compensation re-estimated between them")
            .atLeast(1)
            .cli("compensation-rounds"));
  visit(&S::tolerance, Field("tolerance",
                             "another round only when the match moved the velocity by more "
                             "(yaw rate x 10 m)")
                           .unit("m/s")
                           .atLeast(0)
                           .orInfinite()
                           .cli("compensation-tolerance"));
}

/// Each point moved from the vehicle pose at its time_offset τ to the pose at τ = 0, assuming the
/// constant body-frame velocity (vx, vy, ω) in m/s and rad/s; covariances are rotated with it and
/// time offsets set to 0. Points without a finite time offset are left as they are. Throws
/// std::invalid_argument when the offsets span more than 10 s.
void compensateMotion(const pcl::PointCloud<PointRadar>& in, const Pose2& velocity, pcl::PointCloud<PointRadar>& out);

}  // namespace radar_ndt
