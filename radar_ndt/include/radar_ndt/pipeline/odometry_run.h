#pragma once
// One entry for a whole run, whoever runs it: radar_odometry, Python's run_* and radar_batch's
// tasks open a source here and run it to its end; the ROS node feeds the same per-cycle and
// per-scan steps message by message (AutomotiveStream, ScanningStream). A source is a dataset
// folder (a nuScenes scene, an Oxford, RADIATE or Boreas sequence) or a recording read through a
// sensor description (a ROS 1 bag: radar_ndt/io/recording.h); its options are made once, here,
// from the caller's settings over the defaults for the radar it holds, and checked against what it
// holds (the car's sensors a method fuses, a ground truth to evaluate against).
//
//   OdometryRun run({"oxford", "../shared/data/oxford-radar-real"}, {{"matcher.grid", 4.0}});
//   const ScanningRunResult r = run.runScanning();

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/inertial_run.h"
#include "radar_ndt/pipeline/run_settings.h"
#include "radar_ndt/pipeline/scanning_run.h"

namespace radar_ndt {

/// Where a run reads from.
struct RunSource {
  std::string format;   ///< nuscenes | rosbag | oxford | radiate | boreas
  std::string path;     ///< the nuScenes dataroot, the sequence folder, or the recording
  std::string scene;    ///< nuscenes: the scene's name ("all" or empty: every scene, openAll)
  std::string version;  ///< nuscenes: the tables' folder (empty: the one holding sensor.json)
  std::string sensors;  ///< rosbag: the sensor description (a YAML file, or preset:NAME)
};

/// Automotive and Scanning are planar; Inertial is the 6-DoF run of a 4D radar (inertial_run.h).
enum class PipelineKind { Automotive, Scanning, Inertial };

/// The formats a source may have, for messages: "nuscenes, rosbag, oxford, radiate, boreas".
std::string runFormats();

/// The pipeline a source runs: nuscenes automotive; oxford, radiate, boreas scanning; a recording
/// by its description (one scanning radar: scanning; point-cloud radars: automotive, read here),
/// or, for point-cloud radars, the 6-DoF one when `given` asks for a 6-DoF method
/// (matcher.method: isInertialMethod).
PipelineKind pipelineOf(const RunSource& source, const Settings& given = {});

/// A recording's description with the settings that say which radars run applied, as the
/// offline run and the ROS node apply them: sequence.reference_channel and sequence.channels when
/// set, sequence.filter.max_range when given (the description's own range holds otherwise). The
/// nuScenes reader's keep lists given are refused (SettingError): a description keeps its own.
SensorDescription describedSensors(SensorDescription description, const AutomotiveRunOptions& options,
                                   const Settings& given);

class OdometryRun {
 public:
  using Progress = std::function<void(std::size_t, std::size_t)>;
  /// Called after each step with its index, the step and its points (CycleCallback, ScanCallback).
  using StepCallback = std::function<void(std::size_t, const OdometryStep&, const pcl::PointCloud<PointRadar>&)>;

  /// Opens `source` (one nuScenes scene; a sequence indexed; a recording read) and makes its
  /// options from `given` over the defaults for its radar (automotiveRunOptions,
  /// scanningRunOptions over defaultScanningOptions). A recording's description takes the
  /// settings that say which radars a run uses (sequence.reference_channel, sequence.channels,
  /// sequence.filter.max_range). Throws SettingError for a setting the pipeline that runs does not
  /// use, std::invalid_argument for a method that fuses sensors the recording lacks or a bad
  /// source, IoError for an unreadable one.
  OdometryRun(const RunSource& source, const Settings& given);
  /// Every scene of a nuScenes dataroot for scene "all" (or empty), sharing its tables; one run
  /// otherwise.
  static std::vector<OdometryRun> openAll(const RunSource& source, const Settings& given);
  OdometryRun(OdometryRun&&) noexcept;
  OdometryRun& operator=(OdometryRun&&) noexcept;
  ~OdometryRun();

  PipelineKind pipeline() const;
  /// The scene's, sequence's or recording's name.
  const std::string& name() const;
  const RunSource& source() const;
  /// The options it runs with (std::logic_error for the other pipeline's).
  const AutomotiveRunOptions& automotiveOptions() const;
  const ScanningRunOptions& scanningOptions() const;
  const InertialRunOptions& inertialOptions() const;
  /// Whether there is a ground truth to evaluate against; without, `why_not` says where it would be.
  bool hasGroundTruth(std::string* why_not = nullptr) const;

  /// Runs to the end (std::logic_error for the other pipeline's).
  AutomotiveRunResult runAutomotive(const Progress& progress = nullptr, const StepCallback& on_step = nullptr) const;
  ScanningRunResult runScanning(const Progress& progress = nullptr, const StepCallback& on_step = nullptr) const;
  InertialRunResult runInertial(const Progress& progress = nullptr,
                                const InertialStepCallback& on_step = nullptr) const;

  struct Impl;  ///< what was opened (opaque)

 private:
  explicit OdometryRun(std::unique_ptr<Impl> impl);
  AutomotiveRunResult runAutomotiveWith(const AutomotiveRunOptions& options, const Progress& progress,
                                        const StepCallback& on_step) const;
  friend void runSideBySide(const std::vector<OdometryRun>&,
                            const std::function<void(std::size_t, const AutomotiveRunResult&)>&, const Progress&);
  std::unique_ptr<Impl> impl_;
};

/// Runs automotive `runs` (the scenes of openAll) and calls `done(i, result)` for runs[i] in order,
/// one call at a time: with more than one thread and more than one run, side by side, one thread
/// each (a scene's cycles are short: whole scenes at once keep every core busy where one scene's
/// pipeline cannot); each result is the one its run gives alone. `progress(done, total)` counts runs.
void runSideBySide(const std::vector<OdometryRun>& runs,
                   const std::function<void(std::size_t, const AutomotiveRunResult&)>& done,
                   const OdometryRun::Progress& progress = nullptr);

}  // namespace radar_ndt
