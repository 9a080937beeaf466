#pragma once
// The 6-DoF run of a 4D radar recording (issue: 4D radar, part 2): one radar's scans with the
// rig's 6-axis IMU through the radar-inertial odometry (odometry/radar_inertial_odometry.h), radar
// only by default, the IMU fused on request, or the doppler-imu baseline (odometry/doppler_imu.h).
// The one entry (odometry_run.h) opens a recording and runs it here; the ROS node feeds
// InertialStream message by message, so a live run and an offline one give the same poses.
//
//   const InertialRunResult r = runInertialOdometry(cycles, imu, inertialRunOptions({{"imu", true}}));

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <pcl/point_cloud.h>

#include "radar_ndt/fields.h"
#include "radar_ndt/frontend/point_covariance.h"
#include "radar_ndt/io/imu_sample.h"
#include "radar_ndt/io/radar_cycle.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/odometry/doppler_imu.h"
#include "radar_ndt/odometry/radar_inertial_odometry.h"
#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// The methods of the 6-DoF pipeline: the 3D matchers of the registry, then doppler-imu.
std::vector<std::string> inertialMethods();
/// Whether `method` is one of them (what makes a recording's run the 6-DoF one).
bool isInertialMethod(const std::string& method);
/// "pw-ndt-3d | pcl-ndt-3d | pcl-gicp | doppler-imu", for the settings' help.
std::string inertialMethodChoices();

struct InertialMatcherOptions {
  std::string method = "pw-ndt-3d";
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void InertialMatcherOptions::fields(Visit&& visit) {
  visit(&InertialMatcherOptions::method,
        Field("method", "the matcher, by its registered name").cli("method").choices(&inertialMethodChoices));
}

struct InertialRunOptions {
  InertialMatcherOptions matcher;
  /// Fuse the rig's IMU (the description's imu topic). Radar only by default, as the planar
  /// pipelines; doppler-imu needs it.
  bool imu = false;
  /// The scans' recorded times minus their measurement's (a driver's latency), taken off every
  /// scan's stamp before either method.
  double radar_latency = 0.0;
  /// Each detection's 1σ in range, azimuth and elevation: its covariance (point_covariance.h).
  /// The reference radar's, and every radar's without one of its own below.
  SphericalAccuracy accuracy;
  /// The other radars' own accuracies, by sensor id (the description's radar index): their
  /// descriptions' spherical_accuracy (inertialRunDefaults). An accuracy given as a setting is every
  /// radar's (inertialRunOptions empties this). Not a setting itself: the description says it.
  std::map<std::uint16_t, SphericalAccuracy> radar_accuracy;
  /// The accuracy of radar `sensor_id`'s detections.
  const SphericalAccuracy& accuracyOf(std::uint16_t sensor_id) const {
    const auto it = radar_accuracy.find(sensor_id);
    return it == radar_accuracy.end() ? accuracy : it->second;
  }
  RadarInertialOptions odometry;
  DopplerImuOptions doppler_imu;
  std::size_t max_cycles = 0;  ///< 0: all
  /// Radars not triggered together: each cycle's sweeps (the reference's and the others' within a
  /// period before it) one step at the reference's time, each de-skewed by its offset
  /// (odometry.deskew); off, a step for each sweep time. One radar, or radars triggered together,
  /// run the same either way.
  bool merge_sweeps = true;
  /// Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void InertialRunOptions::fields(Visit&& visit) {
  using S = InertialRunOptions;
  visit(&S::matcher, Field("matcher", "the matcher"));
  visit(&S::imu,
        Field("imu", "fuse the rig's IMU").onSwitch("imu", "fuse the rig's 6-axis IMU (the description's imu topic)"));
  visit(&S::radar_latency, Field("radar_latency", "the scans' recorded times minus their measurement's")
                               .unit("s")
                               .atLeast(0)
                               .cli("radar-latency"));
  visit(&S::accuracy, Field("accuracy", "each detection's accuracy, its covariance's source"));
  visit(&S::odometry, Field("odometry", "the 6-DoF odometry"));
  visit(&S::doppler_imu, Field("doppler_imu", "the doppler-imu baseline"));
  visit(&S::merge_sweeps,
        Field("merge_sweeps", "several radars: a cycle's sweeps one step, each de-skewed to the latest's time")
            .offSwitch("no-merge-sweeps", "several 4D radars: a step for each sweep time, not one a cycle"));
  visit(&S::max_cycles,
        Field("max_cycles", "stop after this many cycles per scene, or scans (0: all)").cli("max-cycles"));
}

struct InertialRunResult {
  std::string sequence;  ///< the recording's name
  std::string method = "pw-ndt-3d";
  bool imu = false;
  std::string radar;       ///< the reference channel
  std::size_t radars = 0;  ///< how many radars ran (their sweeps, each through its mounting)
  double period_s = 0;
  std::string prior;  ///< what each match started from
  Trajectory estimate;
  Trajectory ground_truth;            ///< the recording's 6-DoF truth at the poses' stamps; empty without one
  std::vector<OdometryStep3D> steps;  ///< every scan's, skipped ones included
  std::vector<std::string> problems;
  std::size_t scans = 0, matched = 0, fallbacks = 0, still = 0, skipped = 0, unreadable = 0;
  double seconds = 0;  ///< wall time of the run
};

/// The defaults of a 6-DoF run whose reference radar is `radar` (its name) in `d`: each radar's
/// detections take its description's spherical_accuracy where it has one (the reference's as
/// `accuracy`, the others' in `radar_accuracy`); the settings given go over them.
InertialRunOptions inertialRunDefaults(const SensorDescription& d, const std::string& radar);

/// A 4D radar's detections (PointRadar as a recording reads them: sensor frame, Doppler positive
/// receding) as PointRadar4D with `accuracy`'s covariance, in the sensor frame.
pcl::PointCloud<PointRadar4D> toRadar4D(const pcl::PointCloud<PointRadar>& points, const SphericalAccuracy& accuracy);

/// A cycle's sweeps as the 6-DoF run takes them, in time order, each group's sweeps in radar order:
/// grouped by their recorded time (a group is one step: the sweeps of radars triggered together),
/// or with `merge` all of them one group, a step at the latest sweep's time (InertialStream
/// de-skews the earlier ones).
std::vector<std::vector<RadarSweepData>> sweepsByTime(std::vector<RadarSweepData> sweeps, bool merge = false);

/// The live side: IMU messages and the radars' scans as they come, in time order; what the ROS
/// node runs, message by message. Not for doppler-imu (a whole-run smoother: runInertialOdometry).
class InertialStream {
 public:
  /// `radar_to_body`: the radar's mounting. std::invalid_argument for doppler-imu or bad options.
  InertialStream(const InertialRunOptions& options, const Eigen::Isometry3d& radar_to_body);
  void addImu(const ImuSample& sample);
  /// One scan, its recorded stamp (s; radar_latency is taken off here).
  OdometryStep3D addScan(double stamp, const pcl::PointCloud<PointRadar>& points);
  /// The sweeps of several radars as one step at `stamp` (s, the latest sweep's recorded time),
  /// each with its mounting (`sensor_to_vehicle`) and radar (`sensor_id`)
  /// (RadarInertialOdometry::addScans); an earlier sweep's detections are de-skewed by how much
  /// earlier it was (merge_sweeps).
  OdometryStep3D addScans(double stamp, const std::vector<RadarSweepData>& sweeps);
  const RadarInertialOdometry& odometry() const { return odometry_; }

 private:
  InertialRunOptions options_;
  RadarInertialOdometry odometry_;
};

using InertialStepCallback =
    std::function<void(std::size_t, const OdometryStep3D&, const pcl::PointCloud<PointRadar4D>&)>;

/// Runs `cycles` with `imu` (base frame, time-ordered) to the end: every radar's sweeps in time
/// order, each with its mounting, those recorded at one time as one step (one radar: a step a
/// scan). Each IMU message is handed over before the scans after it, as the stream gets them live.
/// `progress(done, total)` after each cycle; `on_step(k, step, scan)` (k the cycle) with the step's
/// detections in the body frame.
InertialRunResult runInertialOdometry(const RadarCycleSource& cycles, const std::vector<ImuSample>& imu,
                                      const InertialRunOptions& options,
                                      const std::function<void(std::size_t, std::size_t)>& progress = nullptr,
                                      const InertialStepCallback& on_step = nullptr);

/// A 6-DoF trajectory projected onto the plane: x, y and the heading (the body's x axis turned
/// into the plane), z, roll and pitch dropped; what planar (nuScenes-style) tables compare.
Trajectory projectToPlane(const Trajectory& trajectory);

}  // namespace radar_ndt
