#pragma once
// radar_ndt::ScanningOdometry: the paper's scanning pipeline after the front-end (Sec. III-E,
// IV-A, Oxford). Each thresholded scan is matched from a constant-velocity guess; a match that
// does not converge or that the motion gate refuses (an acceleration above 8 m/s²) is retried
// with the grid enlarged by 2.5 m, and once the grid exceeds 12.5 m, with the power shift s halved
// (a bus or truck filling the view); if nothing passes the scan keeps the constant-velocity
// motion. Below 1.5 km/h the grid is 1.5 m. Beyond the paper: each scan is matched to a keyframe
// (KeyframePolicy), points are moved to the scan's reference time (motion compensation, iterated
// with the match), and a match that fits far worse than recent ones is refused (FitHistory).

#include <cstdint>
#include <memory>
#include <vector>

#include <pcl/point_cloud.h>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/odometry/fit_history.h"
#include "radar_ndt/odometry/gyro_yaw.h"
#include "radar_ndt/odometry/keyframe_policy.h"
#include "radar_ndt/odometry/keyframe_target.h"
#include "radar_ndt/odometry/matcher.h"
#include "radar_ndt/odometry/motion_compensation.h"
#include "radar_ndt/odometry/motion_gate.h"
#include "radar_ndt/odometry/motion_model.h"
#include "radar_ndt/odometry/odometry_step.h"
#include "radar_ndt/point_types.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/time_series.h"

namespace radar_ndt {

/// The scanning pipeline's settings, the paper's Oxford values by default.
struct ScanningOdometryOptions {
  // The failure ladder; the grid g and power shift s it starts from are the matcher's
  // (MatcherOptions, MatcherAdapter::nominal).
  double grid_step = 2.5;         ///< added to g after each failed attempt
  double max_grid = 12.5;         ///< once an attempt above this grid fails, s is halved
  int max_shift_halvings = 1;     ///< grid ladders tried with a halved s before falling back
  double slow_speed = 1.5 / 3.6;  ///< m/s: below this estimated speed the grid is slow_grid
  double slow_grid = 1.5;         ///< m
  ScanningMotionGateOptions gate;
  MotionCompensationOptions compensation;
  std::size_t min_points = 30;  ///< fewer points in either scan: constant velocity
  /// The second scan has no velocity to extrapolate: it is matched from each of these forward
  /// displacements (m) and the best-scoring result is its guess. Empty: from zero motion.
  std::vector<double> start_hypotheses{0.0, 1.5, 3.0, 4.5, 6.0, -1.5};
  KeyframeOptions keyframes;
  /// Judged at the nominal grid and power shift (WeightedNDT2D only). A candidate found by the retry ladder
  /// is refined at the nominal settings and judged there.
  FitCheckOptions fit;
  /// A yaw-rate gyro (gyro_yaw.h), used once setYawRate gave its signal.
  GyroOptions gyro;
  /// Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void ScanningOdometryOptions::fields(Visit&& visit) {
  using S = ScanningOdometryOptions;
  visit(&S::grid_step, Field("grid_step", "added to g after each failed attempt").unit("m").positive());
  visit(&S::max_grid, Field("max_grid", "once an attempt above this grid fails, s is halved").unit("m").atLeast(0));
  visit(&S::max_shift_halvings, Field("max_shift_halvings", "grid ladders tried with a halved s").atLeast(0));
  visit(&S::slow_speed,
        Field("slow_speed", "below this estimated speed the grid is slow_grid").unit("m/s").atLeast(0).orInfinite());
  visit(&S::slow_grid, Field("slow_grid", "the grid below slow_speed").unit("m").positive());
  visit(&S::gate, Field("gate", "the motion gate"));
  visit(&S::compensation, Field("compensation", "the points' motion compensation"));
  visit(&S::min_points, Field("min_points", "fewer points in either scan: constant velocity").atLeast(0));
  visit(&S::start_hypotheses,
        Field("start_hypotheses", "the second scan is matched from each of these forward displacements").unit("m"));
  visit(&S::keyframes, Field("keyframes", "when the keyframe is replaced"));
  visit(&S::fit, Field("fit", "the fit check against recent matches"));
  visit(&S::gyro, Field("gyro", "a yaw-rate gyro's rotation as prior, de-skew and measurement"));
}

/// One thresholded scan: points in the vehicle frame, each with its time_offset (s) from
/// `timestamp_us`, the scan's reference time (the pose is the vehicle's at that time).
struct ScanFrame {
  std::int64_t timestamp_us = 0;
  pcl::PointCloud<PointRadar>::ConstPtr cloud;
};

class ScanningOdometry {
 public:
  /// An empty `matcher`: constant velocity throughout. Each step starts at the matcher's nominal
  /// grid and power shift (MatcherAdapter::nominal). Validates `options`.
  ScanningOdometry(const ScanningOdometryOptions& options, MatcherAdapter matcher);

  /// Adds a thresholded scan (planar, in the vehicle frame at its reference time). Nothing keeps a
  /// pointer to the scan's cloud after it returns: the odometry copies what it needs.
  const OdometryStep& addScan(const ScanFrame& scan);
  /// A scan at `timestamp_us` that could not be read (corrupt or missing file): a Bridged step
  /// whose pose continues the last step at its velocity. Matching state is untouched, so the next
  /// scan is matched against the keyframe across the gap.
  const OdometryStep& bridge(std::int64_t timestamp_us) { return log_.bridge(timestamp_us, motion_model_); }
  /// The gyro's yaw rate (rad/s, counter-clockwise positive, on its own clock: options.gyro's
  /// time_offset), used from the next scan on when options.gyro.enabled.
  void setYawRate(TimeSeries yaw_rate) { yaw_rate_ = std::make_shared<const TimeSeries>(std::move(yaw_rate)); }
  /// The same for a series that grows as samples arrive (a live gyro): the step integrates what it
  /// holds then.
  void setYawRate(std::shared_ptr<const TimeSeries> yaw_rate) { yaw_rate_ = std::move(yaw_rate); }
  /// Whether the steps use a gyro.
  bool usesGyro() const { return options_.gyro.enabled && yaw_rate_ && !yaw_rate_->empty(); }
  /// The gyro's bias as estimated so far (rad/s).
  double gyroBias() const { return gyro_.bias(); }

  const std::vector<OdometryStep>& steps() const { return log_.steps(); }
  const OdometryCounters& counters() const { return log_.counters(); }
  const ScanningOdometryOptions& options() const { return options_; }
  /// Poses of all non-skipped steps (bridged ones included), stamps in seconds.
  Trajectory trajectory() const { return log_.trajectory(); }
  /// What the next scan is matched against: the keyframe at its reference time (motion-compensated
  /// with its estimated velocity when compensation is on).
  pcl::PointCloud<PointRadar>::ConstPtr keyframeCloud() const { return target_.cloud(); }

 private:
  /// What one step's attempts share.
  struct Attempt {
    const pcl::PointCloud<PointRadar>* raw;  ///< the scan as given
    Pose2 prev_in_keyframe;                  ///< the previous scan's pose in the keyframe's frame
    bool target_is_previous;                 ///< the keyframe is the previous scan
    double dt, mid_time;                     ///< the interval (s) and its middle (s)
    double yaw_rate;                         ///< rad/s the sweep is de-skewed with (NaN: the match's)
  };

  const OdometryStep& addFirstScan(const ScanFrame& scan, OdometryStep& step);
  /// Matching with the paper's failure handling: the accepted motion, or the guess (step's status,
  /// attempts, grid and power shift set).
  Pose2 matchWithFailureHandling(const ScanFrame& scan, const OdometryStep& prev, double dt, OdometryStep& step);
  /// The nominal grid (or the slow one) and power shift, then the keyframe as the target.
  void prepareMatcher(double grid);
  /// The second scan: the best-scoring match from each start hypothesis (the guess otherwise).
  Pose2 bestStartHypothesis(const ScanFrame& scan, const Pose2& guess);
  /// The grid ladder, then with s halved; a candidate off the nominal settings is refined there,
  /// and judged matches must fit as well as recent ones. True with `*motion` set when one passed.
  bool runRetryLadder(const Attempt& a, const Pose2& guess, double nominal_grid, OdometryStep& step, Pose2* motion);
  /// One attempt at the current matcher settings: match (≤ compensation rounds), then the gate.
  bool attempt(const Attempt& a, const Pose2& from, OdometryStep& step, Pose2* estimate);
  /// A candidate the ladder found off the nominal settings, refined there and judged by its fit.
  bool refineAtNominal(const Attempt& a, OdometryStep& step, Pose2* estimate);
  /// Whether a converged, gated match fits as well as recent ones (judged fits enter the history).
  bool fitsLikeRecentMatches(bool judged, OdometryStep& step);
  /// Match, re-compensate, match again (≤ rounds) from `guess` (the motion from the previous scan).
  bool matchScan(const Attempt& a, const Pose2& guess, Pose2* estimate, int* rounds);
  /// The scan as the next target, or the first scan compensated once a velocity is known.
  void updateKeyframe(const ScanFrame& scan, OdometryStep& step, double dt);
  /// The gyro's yaw over [t0, t1] as the prior's yaw (usesGyro()).
  void gyroPrior(std::int64_t t0_us, std::int64_t t1_us, double dt, OdometryStep& step);

  ScanningOdometryOptions options_;
  MatcherAdapter matcher_;
  ScanningMotionGate gate_;
  KeyframePolicy keyframes_;
  KeyframeTarget target_;
  FitHistory fits_;
  ConstantVelocityModel motion_model_;
  StepLog log_;
  std::shared_ptr<const TimeSeries> yaw_rate_;  ///< the gyro's, when given
  GyroYaw gyro_;
  pcl::PointCloud<PointRadar>::Ptr compensated_;  ///< scratch: the source of the last attempt
  pcl::PointCloud<PointRadar> aligned_;           ///< scratch: the matcher's output (unused; kept to reuse its memory)
};

}  // namespace radar_ndt
