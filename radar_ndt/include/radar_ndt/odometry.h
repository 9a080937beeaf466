#pragma once
// radar_ndt::Odometry: the paper's automotive pipeline after the front-end (Sec. III-B, IV-A):
// at each cycle the probabilistic submap of cycles k−N+1..k is matched to the submap of cycles
// k−N..k−1, starting from the Doppler ego-velocity integral. A match is a failure when it does not
// converge, when it implies an acceleration above the motion prior (8 m/s²) beyond what matching
// noise explains, or when it disagrees with the Doppler ego-velocity (chi-square test with the
// ego-velocity's and the match's covariance). A failure is retried with the grid enlarged (+2 m,
// up to 4 times); if all fail, the cycle falls back to the ego-velocity integral. Any
// pcl::Registration<PointRadar, PointRadar> can be the matcher.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/matchers.h"
#include "radar_ndt/probabilistic_submap.h"
#include "radar_ndt/radar_cycle.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

struct OdometryOptions {
  std::size_t submap_size = 3;   ///< N cycles a submap
  double grid = 3.0;             ///< g (m), the paper's nuScenes value
  double grid_step = 2.0;        ///< added to g at each retry
  int max_retries = 4;
  double max_acceleration = 8.0; ///< motion prior (m/s²)
  /// Matching noise allowed on top of the motion prior and in the chi-square test: 1σ of a
  /// match's translation (m) and rotation (rad).
  double match_sigma_xy = 0.05;
  double match_sigma_yaw = 0.005;
  /// false: a converged match is always accepted (no motion-prior or Doppler check), as plain
  /// submap matching (Holder et al.) does.
  bool gate = true;
  double chi2_threshold = 16.27;  ///< 3 degrees of freedom, 99.9 %
  /// Added to the ego-velocity covariance of a cycle whose velocity could not be estimated (the
  /// previous one is reused): 1σ in m/s and rad/s.
  double stale_velocity_sigma = 0.5;
  std::size_t min_points = 10;    ///< fewer points in either submap: no match, dead reckoning
  /// Rapp et al.: weight each source point by exp(−½(Δv_r/σ)²), Δv_r its Doppler minus the one the
  /// current motion estimate predicts, re-weighted `doppler_weight_rounds` times.
  bool doppler_weights = false;
  double doppler_weight_sigma = 0.15;
  int doppler_weight_rounds = 2;
};

enum class StepStatus {
  First,     ///< the first cycle: identity
  Matched,   ///< the match passed the checks at the nominal grid
  Retried,   ///< passed after the grid was enlarged
  Fallback,  ///< every attempt failed: ego-velocity integral
  DeadReckoned,  ///< no matcher (Method::Doppler), or too few points to match
  Skipped,   ///< timestamp not after the previous cycle's: no pose
};
const char* toString(StepStatus s);

struct OdometryStep {
  std::int64_t timestamp_us = 0;
  Pose2 pose = Pose2::Zero();    ///< vehicle at this cycle in the first cycle's frame
  Pose2 motion = Pose2::Zero();  ///< this cycle in the previous one
  Pose2 doppler_motion = Pose2::Zero();  ///< the ego-velocity integral (the initial guess)
  StepStatus status = StepStatus::First;
  int attempts = 0;
  double grid = 0;
  double chi2 = 0;
  double match_ms = 0;
  double submap_ms = 0;
  std::size_t source_points = 0, target_points = 0;
  bool velocity_valid = true;
};

struct OdometryCounters {
  std::size_t cycles = 0, matched = 0, retried = 0, fallbacks = 0, dead_reckoned = 0, skipped = 0, stale_velocity = 0;
};

class Odometry {
 public:
  /// `matcher` nullptr: dead reckoning with the Doppler ego-velocity (Kellner's baseline).
  Odometry(const OdometryOptions& options, RadarRegistration::Ptr matcher);

  /// Adds a front-end cycle. Its cloud is planar (z = 0, as AutomotiveFrontEnd gives it): ours
  /// ignores z, PCL's 3D matchers would not.
  const OdometryStep& add(const ProcessedCycle& cycle);

  const std::vector<OdometryStep>& steps() const { return steps_; }
  const OdometryCounters& counters() const { return counters_; }
  const OdometryOptions& options() const { return options_; }
  /// Poses of all non-skipped steps, stamps in seconds.
  Trajectory trajectory() const;

 private:
  bool accept(const Pose2& motion, const Pose2& guess, const Eigen::Matrix3d& guess_cov, double dt, double* chi2) const;
  void weightByDoppler(pcl::PointCloud<PointRadar>& cloud, const std::vector<SensorMounting>& mountings, const Pose2& motion,
                       double dt) const;

  OdometryOptions options_;
  RadarRegistration::Ptr matcher_;
  ProbabilisticSubmap submap_;
  pcl::PointCloud<PointRadar>::Ptr target_;
  std::vector<OdometryStep> steps_;
  OdometryCounters counters_;
  EgoVelocity last_velocity_;
  bool have_velocity_ = false;
  Pose2 last_accepted_motion_ = Pose2::Zero();
  double last_dt_ = 0;
};

}  // namespace radar_ndt
