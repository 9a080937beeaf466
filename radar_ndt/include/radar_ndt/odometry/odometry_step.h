#pragma once
// What both odometries record per cycle or scan (OdometryStep), their counters, and the step log
// they share: skipped and bridged steps, the last processed step, the trajectory. The counters are
// derived from the steps in one place (StepLog::add): an odometry records what happened in the
// step, never in a counter.

#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/odometry/motion_model.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

enum class StepStatus {
  First,         ///< the first cycle: identity
  Matched,       ///< the match passed the checks at the nominal grid
  Retried,       ///< passed after the grid was enlarged
  Fallback,      ///< every attempt failed: ego-velocity integral (scanning: constant velocity)
  DeadReckoned,  ///< no matcher (Method::Doppler), or too few points to match (too_few_points; scanning: constant
                 ///< velocity)
  Skipped,       ///< timestamp not after the previous cycle's: no pose
  Bridged,       ///< the scan or cycle could not be read (bridge()): pose from the motion model, not matched
};
const char* toString(StepStatus s);

struct OdometryStep {
  std::int64_t timestamp_us = 0;
  Pose2 pose = Pose2::Zero();    ///< vehicle at this cycle in the first cycle's frame
  Pose2 motion = Pose2::Zero();  ///< this cycle in the previous one
  Pose2 prior_motion =
      Pose2::Zero();  ///< the initial guess: the Doppler ego-velocity integral (scanning: constant velocity)
  StepStatus status = StepStatus::First;
  int attempts = 0;
  /// DeadReckoned although there is a matcher: the scan (or cycle) or its target had fewer points
  /// than the odometry's min_points.
  bool too_few_points = false;
  double grid = 0;
  double match_ms = 0;
  std::size_t source_points = 0, target_points = 0;
  // Automotive only:
  double chi2 = 0;  ///< of the accepted (or last) match against the Doppler motion
  double submap_ms = 0;
  bool velocity_valid = true;  ///< the cycle had its own ego-velocity (not the last one reused)
  /// The accepted match before it was fused with the Doppler motion (zero without one).
  Pose2 match_motion = Pose2::Zero();
  /// Covariances as their sources report them, before calibration: the ego-velocity fit's motion
  /// covariance, and the matcher's pose covariance (NaN for a matcher without one, or no match).
  Eigen::Matrix3d prior_covariance = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d match_covariance = Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  double yaw_rate_bias = 0;  ///< the fusion's Doppler yaw-rate bias estimate after this cycle (rad/s)
  // Scanning only:
  float power_shift = 0;           ///< s of the accepted (or last) attempt
  int compensation_rounds = 0;     ///< matches run with motion-compensated points, all attempts
  bool slow = false;               ///< the slow-speed grid was used
  bool keyframe = false;           ///< this scan became the target of the next matches
  bool shift_halved = false;       ///< the accepted match (or the fallback) needed s halved
  int attempts_not_converged = 0;  ///< attempts that did not converge
  int attempts_rejected = 0;       ///< converged attempts the motion prior refused
  int attempts_poor_fit = 0;       ///< converged attempts refused for a fit far below recent matches
};

/// How many steps ended each way, derived from the steps (StepLog::add, countStep): first,
/// matched, retried, fallbacks, dead_reckoned, skipped and bridged add up to `cycles`.
struct OdometryCounters {
  std::size_t cycles = 0, first = 0, matched = 0, retried = 0, fallbacks = 0, dead_reckoned = 0, skipped = 0,
              bridged = 0;
  std::size_t too_few_points = 0;  ///< of the dead-reckoned steps, those a matcher could not match
  /// Steps that a matcher should have matched and did not (fallbacks, too few points, unreadable
  /// scans bridged), of those it could have (all but the first and the skipped).
  std::size_t unmatched() const { return fallbacks + too_few_points + bridged; }
  std::size_t matchable() const { return cycles - first - skipped; }
  /// More than half the matchable steps were not matched: the trajectory is mostly dead reckoning.
  bool mostlyUnmatched() const { return matchable() > 0 && 2 * unmatched() > matchable(); }
  // Automotive only:
  std::size_t stale_velocity = 0;  ///< cycles without their own ego-velocity
  // Scanning only:
  std::size_t shift_halved = 0;   ///< steps whose accepted match (or fallback) needed s halved
  std::size_t slow = 0;           ///< steps matched at the slow-speed grid
  std::size_t not_converged = 0;  ///< attempts that did not converge
  std::size_t rejected = 0;       ///< converged attempts rejected by the motion prior
  std::size_t poor_fit = 0;       ///< converged attempts rejected for a fit far below recent matches
};

/// The steps of one run and their counters.
class StepLog {
 public:
  /// A new step at `timestamp_us` (not yet recorded).
  OdometryStep begin(std::int64_t timestamp_us);
  /// The last step that was processed: neither skipped nor bridged (nullptr before the first).
  const OdometryStep* previous() const;
  /// Records `step`, counts it (countStep) and returns the stored copy.
  const OdometryStep& add(const OdometryStep& step);
  /// Records `step` as skipped: its timestamp does not advance past `prev`'s.
  const OdometryStep& addSkipped(OdometryStep step, const OdometryStep& prev);
  /// A scan or cycle at `timestamp_us` that could not be read: a Bridged step whose pose continues
  /// the last step by `model`'s prediction. Before the first step, or at a timestamp not after
  /// the last one, the step is Skipped (no pose).
  const OdometryStep& bridge(std::int64_t timestamp_us, const ConstantVelocityModel& model);

  const std::vector<OdometryStep>& steps() const { return steps_; }
  const OdometryCounters& counters() const { return counters_; }
  /// Poses of all non-skipped steps (bridged ones included), stamps in seconds.
  Trajectory trajectory() const;

 private:
  std::vector<OdometryStep> steps_;
  OdometryCounters counters_;
};

/// Adds what one recorded step says to `counters`: its status, and for the scanning pipeline its
/// slow grid, halved shift and refused attempts; for the automotive one a reused ego-velocity.
void countStep(const OdometryStep& step, OdometryCounters& counters);

}  // namespace radar_ndt
