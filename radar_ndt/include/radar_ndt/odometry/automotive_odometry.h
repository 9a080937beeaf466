#pragma once
// radar_ndt::AutomotiveOdometry: the automotive pipeline after the front-end, in one of two modes.
//  - SubmapToSubmap, the paper's (Sec. III-B, IV-A): at each cycle the probabilistic submap of
//    cycles k−N+1..k is matched to the submap of cycles k−N..k−1, starting from the Doppler
//    ego-velocity integral. The N−1 cycles the two share are the same points placed by that
//    integral, so the match stays close to it.
//  - CycleToMap (the default, beyond the paper): the newest cycle is matched to a local map of the
//    M cycles before it, placed by the estimated motions, and the match is fused with the Doppler
//    motion (MotionFusion: a Kalman update that also tracks the Doppler yaw-rate bias). The match
//    shares no points with its target, so it is a measurement of its own.
// A match that does not converge, or that the motion gate refuses (an acceleration above the
// motion prior beyond what matching noise explains, or disagreement with the Doppler ego-motion),
// is retried with the grid enlarged; if every attempt fails, the cycle takes the Doppler motion
// (CycleToMap: the bias-corrected prediction). Any pcl::Registration<PointRadar, PointRadar> can be
// the matcher (MatcherAdapter).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "radar_ndt/fields.h"
#include "radar_ndt/frontend/automotive_front_end.h"
#include "radar_ndt/frontend/probabilistic_submap.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/io/vehicle_signals.h"
#include "radar_ndt/odometry/car_fusion.h"
#include "radar_ndt/odometry/local_map.h"
#include "radar_ndt/odometry/matcher.h"
#include "radar_ndt/odometry/motion_fusion.h"
#include "radar_ndt/odometry/motion_gate.h"
#include "radar_ndt/odometry/motion_model.h"
#include "radar_ndt/odometry/odometry_step.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

enum class AutomotiveMatchMode {
  SubmapToSubmap,  ///< the paper's: submap of cycles k−N+1..k to submap k−N..k−1
  CycleToMap,      ///< the newest cycle to the local map of the M cycles before it
};
template <>
struct EnumNames<AutomotiveMatchMode> {
  static constexpr const char* what = "automotive match mode";
  static constexpr EnumName<AutomotiveMatchMode> names[] = {
      {AutomotiveMatchMode::SubmapToSubmap, "submap-to-submap", "submap to submap, not fused: the paper's scheme"},
      {AutomotiveMatchMode::SubmapToSubmap, "paper", ""},
      {AutomotiveMatchMode::CycleToMap, "cycle-to-map",
       "the newest cycle to a local map of earlier cycles, fused with the Doppler motion"}};
};

struct AutomotiveOdometryOptions {
  AutomotiveMatchMode mode = AutomotiveMatchMode::CycleToMap;
  /// N cycles a submap (SubmapToSubmap; CycleToMap matches one cycle and ignores it).
  std::size_t submap_size = 3;
  std::size_t map_cycles = 10;  ///< M cycles in the local map (CycleToMap)
  /// Fuse the accepted match with the Doppler motion (MotionFusion). Off, the match is the motion,
  /// as in the paper.
  bool fuse_doppler = true;
  MotionFusionOptions fusion;
  /// The car's own gyro and wheel speeds (CarFusion), used when given (setVehicleSignals).
  CarSensorOptions car;
  // The retries; the grid g they start from is the matcher's (MatcherOptions, MatcherAdapter::nominal).
  double grid_step = 2.0;  ///< added to g at each retry
  int max_retries = 4;
  AutomotiveMotionGateOptions gate;
  /// Added to the ego-velocity covariance of a cycle whose velocity could not be estimated (the
  /// previous one is reused): 1σ in m/s and rad/s.
  double stale_velocity_sigma = 0.5;
  std::size_t min_points = 10;  ///< fewer points in either submap: no match, dead reckoning
  /// Rapp et al.: weight each point by exp(−½(Δv_r/σ)²), Δv_r its Doppler minus the one its own
  /// cycle's motion predicts, in that cycle's frame: the newest cycle's against the current
  /// estimate, re-weighted `doppler_weight_rounds` times; older cycles keep the weights their own
  /// estimated motion gave them (the first cycle: its Doppler ego-velocity).
  bool doppler_weights = false;
  double doppler_weight_sigma = 0.15;
  int doppler_weight_rounds = 2;
  /// Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
  /// These options in the paper's configuration: SubmapToSubmap with N = `n`, no fusion.
  AutomotiveOdometryOptions paper(std::size_t n) const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void AutomotiveOdometryOptions::fields(Visit&& visit) {
  using S = AutomotiveOdometryOptions;
  visit(&S::mode, Field("mode", "what is matched to what").cli("mode"));
  visit(&S::submap_size, Field("submap_size", "paper mode: N, radar cycles per submap").atLeast(1).cli("submap"));
  visit(&S::map_cycles,
        Field("map_cycles", "cycle-to-map: M, earlier cycles in the local map").atLeast(1).cli("map-cycles"));
  visit(&S::fuse_doppler, Field("fuse_doppler", "fuse the accepted match with the Doppler motion")
                              .offSwitch("no-fusion",
                                         "the accepted match is the motion, not fused with "
                                         "the Doppler motion (ablation; paper mode never fuses)"));
  visit(&S::fusion, Field("fusion", "the fusion's covariances"));
  visit(&S::car, Field("car", "the car's own gyro and wheel speeds"));
  visit(&S::grid_step, Field("grid_step", "added to g at each retry").unit("m").atLeast(0));
  visit(&S::max_retries, Field("max_retries", "retries with a larger grid").atLeast(0));
  visit(&S::gate, Field("gate", "the motion gate"));
  visit(&S::stale_velocity_sigma,
        Field("stale_velocity_sigma", "added to a reused ego-velocity's 1σ").unit("m/s").atLeast(0));
  visit(&S::min_points, Field("min_points", "fewer points in either submap: dead reckoning").atLeast(0));
  visit(&S::doppler_weights, Field("doppler_weights", "Rapp's Doppler-agreement weights (rapp-ndt)"));
  visit(&S::doppler_weight_sigma, Field("doppler_weight_sigma", "σ of Rapp's weights").unit("m/s").positive());
  visit(&S::doppler_weight_rounds, Field("doppler_weight_rounds", "re-weightings of the newest cycle").atLeast(0));
}

class AutomotiveOdometry {
 public:
  /// An empty `matcher` (the method doppler): dead reckoning with the Doppler ego-velocity (Kellner's
  /// baseline). Each cycle's first attempt runs at the matcher's nominal grid, retries enlarge it.
  /// Validates `options`.
  AutomotiveOdometry(const AutomotiveOdometryOptions& options, MatcherAdapter matcher);

  /// Adds a front-end cycle. Its cloud is planar (z = 0, as AutomotiveFrontEnd gives it): ours
  /// ignores z, PCL's 3D matchers would not.
  const OdometryStep& add(const ProcessedCycle& cycle);
  /// A cycle at `timestamp_us` that could not be read: a Bridged step whose pose continues the
  /// last step at its velocity; the submap is untouched.
  const OdometryStep& bridge(std::int64_t timestamp_us) { return log_.bridge(timestamp_us, motion_model_); }
  /// The car's own sensors over the recording, on the radar's clock plus options().car.time_offset;
  /// options().car says which of them are fused (CarFusion). Null: the Doppler prior alone.
  void setVehicleSignals(std::shared_ptr<const VehicleSignals> signals) { signals_ = std::move(signals); }
  /// Whether the car's sensors make the prior (CarFusion).
  bool usesCar() const { return signals_ && options_.car.any(); }

  /// CycleToMap's local map: the last cycles in the newest cycle's vehicle frame (what a ROS node
  /// publishes as its local map).
  const LocalMap& localMap() const { return map_; }

  const std::vector<OdometryStep>& steps() const { return log_.steps(); }
  const OdometryCounters& counters() const { return log_.counters(); }
  const AutomotiveOdometryOptions& options() const { return options_; }

  /// Poses of all non-skipped steps (bridged ones included), stamps in seconds.
  Trajectory trajectory() const { return log_.trajectory(); }

 private:
  /// The cycle's ego-velocity, or the last valid one with its covariance grown.
  EgoVelocity egoVelocityOf(const ProcessedCycle& cycle);
  /// The cycle into the submap (which also integrates the Doppler motion); the submap's cloud.
  pcl::PointCloud<PointRadar>::Ptr addToSubmap(const ProcessedCycle& cycle, const EgoVelocity& ego, double dt,
                                               OdometryStep& step);
  /// The first cycle: identity, and what the next match needs of it.
  const OdometryStep& addFirstCycle(const ProcessedCycle& cycle, const EgoVelocity& ego,
                                    const pcl::PointCloud<PointRadar>::Ptr& submap, OdometryStep& step);
  /// The Doppler motion of the cycle, fused: the bias-corrected prediction (the match's guess).
  MotionEstimate dopplerPrior(double dt, OdometryStep& step);
  /// What the car's sensors measured from t0 to t1 (radar clock).
  CarMotion carMotion(std::int64_t t0_us, std::int64_t t1_us) const;
  /// The prior from the car's sensors and the Doppler motion (CarFusion::predict).
  MotionEstimate carPrior(std::int64_t t0_us, std::int64_t t1_us, double dt, OdometryStep& step);
  /// The match of the cycle (or submap) to its target from `prior`, with retries, fused with the
  /// prior (or, not fused, the match itself); `prior` when nothing was matched.
  MotionEstimate matchAndFuse(const ProcessedCycle& cycle, const pcl::PointCloud<PointRadar>::Ptr& submap,
                              const MotionEstimate& prior, double dt, OdometryStep& step);
  /// Match `source` to the last submap from `guess`, retrying with larger grids; the accepted
  /// motion, or the guess after a fallback (step's status, attempts, grid and χ² set).
  /// Source points from `newest_begin` on are the newest cycle's (the ones Rapp's rounds reweight).
  Pose2 matchWithRetries(const ProcessedCycle& cycle, const pcl::PointCloud<PointRadar>::Ptr& source,
                         std::size_t newest_begin, const pcl::PointCloud<PointRadar>::Ptr& target, const Pose2& guess,
                         const Eigen::Matrix3d& guess_cov, double dt, OdometryStep& step);
  /// Rapp's weights of cloud[first..] against the velocity `v` = (vx, vy, ω) of their cycle.
  void weightByDoppler(pcl::PointCloud<PointRadar>& cloud, const std::vector<SensorMounting>& mountings,
                       const Eigen::Vector3d& v, std::size_t first = 0) const;
  /// After a cycle: what the next match needs of it (the paper's target submap, or the cycle in
  /// the local map, already moved into this cycle's frame), with Rapp's weights from `velocity`.
  void keepForNextMatch(const ProcessedCycle& cycle, const Eigen::Vector3d& velocity,
                        const pcl::PointCloud<PointRadar>::Ptr& submap);
  /// The newest cycle's points weighted against `velocity` (Rapp): what the submap or map keeps.
  pcl::PointCloud<PointRadar> weightedCycle(const ProcessedCycle& cycle, const Eigen::Vector3d& velocity) const;

  AutomotiveOdometryOptions options_;
  MatcherAdapter matcher_;
  AutomotiveMotionGate gate_;
  ProbabilisticSubmap submap_;  ///< the paper's submap; also integrates the Doppler motion
  LocalMap map_;                ///< CycleToMap's target
  MotionFusion fusion_;
  std::shared_ptr<const VehicleSignals> signals_;
  CarFusion car_fusion_;
  MatchCalibration calibration_ = MatchCalibration::WeightedNdt;  ///< how the fusion trusts this matcher's matches
  ConstantVelocityModel motion_model_;
  StepLog log_;
  pcl::PointCloud<PointRadar>::Ptr target_;  ///< the last submap (SubmapToSubmap)
  pcl::PointCloud<PointRadar> aligned_;      ///< the matcher's output (unused; kept to reuse its memory)
  EgoVelocity last_velocity_;
  bool have_velocity_ = false;
};

}  // namespace radar_ndt
