#pragma once
// One odometry run over a nuScenes-layout scene, every stage timed: read → front-end (covariances,
// Doppler ego-velocity, moving detections removed, sweeps to the reference time) → submap →
// match. What `radar_odometry --format nuscenes` runs and what its paper-table mode repeats. The
// next cycles are read and processed on worker threads while one is matched, in order.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "radar_ndt/fields.h"
#include "radar_ndt/frontend/automotive_front_end.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/nuscenes_sequence.h"
#include "radar_ndt/io/radar_cycle.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/io/vehicle_signals.h"
#include "radar_ndt/odometry/automotive_odometry.h"
#include "radar_ndt/odometry/matcher.h"
#include "radar_ndt/odometry/matcher_registry.h"
#include "radar_ndt/pipeline/stage_times.h"

namespace radar_ndt {

struct AutomotiveRunOptions {
  MatcherOptions matcher = MatcherOptions::forAutomotive();
  NuScenesSequenceOptions sequence;
  AutomotiveFrontEndOptions front_end;
  AutomotiveOdometryOptions odometry;
  std::size_t max_cycles = 0;  ///< 0: all
  /// Threads: the next cycles read and through the front-end on the others while one is matched,
  /// the matches in order (the outputs do not depend on it). 0: every core; 1: one thread.
  int threads = 0;
  /// Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void AutomotiveRunOptions::fields(Visit&& visit) {
  using S = AutomotiveRunOptions;
  visit(&S::matcher, Field("matcher", "the matcher"));
  visit(&S::sequence, Field("sequence", "how a scene's sweeps are read and planned into cycles"));
  visit(&S::front_end, Field("front_end", "the automotive front-end"));
  visit(&S::odometry, Field("odometry", "the automotive odometry"));
  visit(&S::max_cycles,
        Field("max_cycles", "stop after this many cycles per scene, or scans (0: all)").cli("max-cycles"));
  visit(&S::threads, Field("threads",
                           "threads: the next scans or cycles read and through the front-end on the others "
                           "while one is matched, several nuScenes scenes side by side (outputs "
                           "identical for any number); 0: every core, 1: one thread")
                         .atLeast(0)
                         .cli("threads"));
}

struct AutomotiveRunResult {
  std::string scene;
  std::string method = "pw-ndt";
  std::size_t submap_size = 0;  ///< N
  std::string reference_channel;
  double period_s = 0;
  std::string prior = "Doppler ego-motion";  ///< what each step's initial guess came from
  Trajectory estimate;
  Trajectory ground_truth;  ///< SE(2), relative to the first cycle
  std::vector<OdometryStep> steps;
  OdometryCounters counters;
  StageTimes median_ms;  ///< per cycle, median of each stage
  StageTimes mean_ms;
  double median_total_ms = 0;  ///< median of the per-cycle totals
  std::vector<std::string>
      problems;  ///< radars that fell silent (first), then files that could not be read, and why (with the cycle)
  std::size_t invalid_velocity_cycles = 0;
  /// Cycles whose ego-velocity used vy = 0 (radars at one place only: EgoVelocityModel::Auto).
  std::size_t nonholonomic_velocity_cycles = 0;
  /// Of those, cycles whose radars sat on the rear axle's line: the forward speed alone, the yaw
  /// rate left to the match (EgoVelocity::forward_only).
  std::size_t forward_speed_cycles = 0;
  std::size_t detections = 0;          ///< after the reader's filters, all cycles
  std::size_t removed_moving = 0;      ///< by the Doppler outlier filter
  double median_doppler_residual = 0;  ///< median over cycles of the ego-velocity fit's inlier RMS (m/s)
  std::vector<double> ego_speed;       ///< Doppler ego speed per cycle (m/s), NaN when invalid
};

/// Called after each cycle with its index, its step and the front-end's cloud (the vehicle frame at
/// the cycle's time, moving detections removed unless the method weighs them), e.g. to build a map;
/// in cycle order, one call at a time, from one of the run's threads.
using CycleCallback = std::function<void(std::size_t, const OdometryStep&, const pcl::PointCloud<PointRadar>&)>;

/// `progress(done, total)` is called after each cycle when given, in order, one call at a time, from
/// one of the run's threads.
AutomotiveRunResult runAutomotiveOdometry(const NuScenesDataset& dataset, const NuScenesScene& scene,
                                          const AutomotiveRunOptions& options,
                                          const std::function<void(std::size_t, std::size_t)>& progress = nullptr,
                                          const CycleCallback& on_cycle = nullptr);

/// Runs `options` on every scene of `scenes` and calls `done(i, result)` for scenes[i] in order, one
/// call at a time, from one of the run's threads. With more than one thread and more than one
/// scene, the scenes run side by side, each on one thread (a scene's cycles are short: running
/// whole scenes at once keeps every core busy where one scene's pipeline cannot); each result is the
/// one runAutomotiveOdometry gives for its scene alone. `progress(done, total)` counts scenes.
void runAutomotiveScenes(const NuScenesDataset& dataset, const std::vector<const NuScenesScene*>& scenes,
                         const AutomotiveRunOptions& options,
                         const std::function<void(std::size_t, const AutomotiveRunResult&)>& done,
                         const std::function<void(std::size_t, std::size_t)>& progress = nullptr);

/// The same with a matcher of the caller's (any pcl::Registration<PointRadar, PointRadar> in a
/// MatcherAdapter, set up as the caller wants, driven from the adapter's nominal grid and power
/// shift); `options.matcher` is not used.
AutomotiveRunResult runAutomotiveOdometry(const NuScenesDataset& dataset, const NuScenesScene& scene,
                                          const AutomotiveRunOptions& options, MatcherAdapter matcher,
                                          const std::function<void(std::size_t, std::size_t)>& progress = nullptr,
                                          const CycleCallback& on_cycle = nullptr);

/// What a run reads: the cycles, and the car's own motion sensors when the recording has them.
struct AutomotiveInputs {
  const RadarCycleSource& cycles;
  /// The car's gyro and wheel speeds; null when the recording has none (then a method that needs
  /// them is refused, and the options' car sensors are left unused).
  std::shared_ptr<const VehicleSignals> car;
  /// Problems met reading the inputs, reported first among the run's.
  std::vector<std::string> problems;
};

/// The run on any source of radar cycles (a nuScenes scene, a ROS bag): what the overloads above
/// run once they have read their scene.
AutomotiveRunResult runAutomotiveOdometry(const AutomotiveInputs& inputs, const AutomotiveRunOptions& options,
                                          MatcherAdapter matcher,
                                          const std::function<void(std::size_t, std::size_t)>& progress = nullptr,
                                          const CycleCallback& on_cycle = nullptr);

/// The automotive run one cycle at a time, as cycles arrive (the ROS node): the front-end, the
/// fallback ego-velocity and the odometry runAutomotiveOdometry runs, so the same cycles give the
/// same steps, and the same result. The cycles' sweeps carry their mountings.
class AutomotiveStream {
 public:
  /// Validates `options` (threads and max_cycles are unused). `car`: the car's signals, which may
  /// grow as samples arrive (required when the options fuse them); `name` names the stream in
  /// results and problems.
  explicit AutomotiveStream(const AutomotiveRunOptions& options, std::shared_ptr<const VehicleSignals> car = nullptr,
                            const std::string& name = "stream");
  ~AutomotiveStream();

  struct Added {
    const OdometryStep& step;  ///< valid until the next add
    /// The front-end's cloud (the vehicle frame at the cycle's time, moving detections removed
    /// unless the method weighs them), as CycleCallback's.
    pcl::PointCloud<PointRadar>::ConstPtr cloud;
    std::vector<std::string> problems;  ///< what the cycle met ("cycle K: ..."), as the run reports it
  };
  /// The next cycle, later than the last.
  Added add(RadarCycle cycle);
  const AutomotiveOdometry& odometry() const;
  /// The run so far as runAutomotiveOdometry reports it (no ground truth; the read time 0).
  AutomotiveRunResult result() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// `options` set for `method` (a name in the registry of matchers): the method, and what it needs
/// beyond it: a matcher with Doppler weights (rapp-ndt; MatcherUses) weighs points by Doppler
/// agreement (odometry.doppler_weights) and so keeps the moving detections (front_end.remove_moving
/// off); the others neither. validate() refuses options that set the method without these,
/// naming the field.
AutomotiveRunOptions withMethod(AutomotiveRunOptions options, const std::string& method);

/// The fusion calibration of the matcher a method builds (AutomotiveOdometry picks the same from
/// its matcher).
MatchCalibration matchCalibrationOf(const std::string& method);

}  // namespace radar_ndt
