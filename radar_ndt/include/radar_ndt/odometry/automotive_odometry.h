#pragma once
// radar_ndt::AutomotiveOdometry: the paper's automotive pipeline after the front-end (Sec. III-B,
// IV-A). At each cycle the probabilistic submap of cycles k−N+1..k is matched to the submap of
// cycles k−N..k−1, starting from the Doppler ego-velocity integral. A match that does not
// converge, or that the motion gate refuses (an acceleration above the motion prior beyond what
// matching noise explains, or disagreement with the Doppler ego-motion), is retried with the grid
// enlarged; if every attempt fails, the cycle falls back to the ego-velocity integral. Any
// pcl::Registration<PointRadar, PointRadar> can be the matcher (MatcherAdapter).

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "radar_ndt/frontend/probabilistic_submap.h"
#include "radar_ndt/frontend/radar_cycle.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/odometry/matcher.h"
#include "radar_ndt/odometry/motion_gate.h"
#include "radar_ndt/odometry/motion_model.h"
#include "radar_ndt/odometry/odometry_step.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

struct AutomotiveOdometryOptions {
  std::size_t submap_size = 3;   ///< N cycles a submap
  double grid = 3.0;             ///< g (m), the paper's nuScenes value
  double grid_step = 2.0;        ///< added to g at each retry
  int max_retries = 4;
  AutomotiveMotionGateOptions gate;
  /// Added to the ego-velocity covariance of a cycle whose velocity could not be estimated (the
  /// previous one is reused): 1σ in m/s and rad/s.
  double stale_velocity_sigma = 0.5;
  std::size_t min_points = 10;   ///< fewer points in either submap: no match, dead reckoning
  /// Rapp et al.: weight each source point by exp(−½(Δv_r/σ)²), Δv_r its Doppler minus the one the
  /// current motion estimate predicts, re-weighted `doppler_weight_rounds` times.
  bool doppler_weights = false;
  double doppler_weight_sigma = 0.15;
  int doppler_weight_rounds = 2;
  /// Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
};

class AutomotiveOdometry {
 public:
  /// An empty `matcher` (Method::Doppler): dead reckoning with the Doppler ego-velocity (Kellner's
  /// baseline). Validates `options`.
  AutomotiveOdometry(const AutomotiveOdometryOptions& options, MatcherAdapter matcher);

  /// Adds a front-end cycle. Its cloud is planar (z = 0, as AutomotiveFrontEnd gives it): ours
  /// ignores z, PCL's 3D matchers would not.
  const OdometryStep& add(const ProcessedCycle& cycle);
  /// A cycle at `timestamp_us` that could not be read: a Bridged step whose pose continues the
  /// last step at its velocity; the submap is untouched.
  const OdometryStep& bridge(std::int64_t timestamp_us) { return log_.bridge(timestamp_us, motion_model_); }

  const std::vector<OdometryStep>& steps() const { return log_.steps(); }
  const OdometryCounters& counters() const { return log_.counters(); }
  const AutomotiveOdometryOptions& options() const { return options_; }
  /// Poses of all non-skipped steps (bridged ones included), stamps in seconds.
  Trajectory trajectory() const { return log_.trajectory(); }

 private:
  /// The cycle's ego-velocity, or the last valid one with its covariance grown.
  EgoVelocity egoVelocityOf(const ProcessedCycle& cycle);
  /// Match `source` to the last submap from `guess`, retrying with larger grids; the accepted
  /// motion, or the guess after a fallback (step's status, attempts, grid and χ² set).
  Pose2 matchWithRetries(const ProcessedCycle& cycle, const pcl::PointCloud<PointRadar>::Ptr& source, const Pose2& guess,
                         const Eigen::Matrix3d& guess_cov, double dt, OdometryStep& step);
  void weightByDoppler(pcl::PointCloud<PointRadar>& cloud, const std::vector<SensorMounting>& mountings, const Pose2& motion,
                       double dt) const;

  AutomotiveOdometryOptions options_;
  MatcherAdapter matcher_;
  AutomotiveMotionGate gate_;
  ProbabilisticSubmap submap_;
  ConstantVelocityModel motion_model_;
  StepLog log_;
  pcl::PointCloud<PointRadar>::Ptr target_;  ///< the last submap
  pcl::PointCloud<PointRadar> aligned_;      ///< the matcher's output (unused; kept to reuse its memory)
  EgoVelocity last_velocity_;
  bool have_velocity_ = false;
};

}  // namespace radar_ndt
