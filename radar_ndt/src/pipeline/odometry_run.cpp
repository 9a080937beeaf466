#include "radar_ndt/pipeline/odometry_run.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "detail/run_timing.h"
#include "pipeline/ordered_pipeline.h"
#include "radar_ndt/io/dataset_format.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/recording.h"
#include "radar_ndt/io/scanning_sequence.h"
#include "radar_ndt/io/sensor_description.h"

namespace radar_ndt {

std::string runFormats() {
  return enumChoices<DatasetFormat>();
}

namespace {
/// Whether `given` asks for a 6-DoF method.
bool asksInertial(const Settings& given) {
  const Setting* m = findSetting(given, "matcher.method");
  return m && m->value.kind() == FieldValue::Kind::Text && isInertialMethod(m->value.text());
}
}  // namespace

PipelineKind pipelineOf(const RunSource& source, const Settings& given) {
  const DatasetFormat f = parseEnum<DatasetFormat>(source.format);
  if (f == DatasetFormat::NuScenes) return PipelineKind::Automotive;
  if (isScanLayout(f)) return PipelineKind::Scanning;
  if (source.sensors.empty())
    throw std::invalid_argument("format rosbag needs a sensor description (a YAML file, or preset:NAME)");
  const SensorDescription d = readSensorDescription(source.sensors);
  if (!d.radars.empty() && d.radars[0].kind == RadarKind::Scanning) return PipelineKind::Scanning;
  return asksInertial(given) ? PipelineKind::Inertial : PipelineKind::Automotive;
}

struct OdometryRun::Impl {
  RunSource source;
  PipelineKind kind = PipelineKind::Automotive;
  std::string name;
  AutomotiveRunOptions automotive;
  ScanningRunOptions scanning;
  InertialRunOptions inertial;
  std::shared_ptr<const NuScenesDataset> dataset;  ///< nuscenes
  const NuScenesScene* scene = nullptr;
  std::unique_ptr<const ScanningSequence> sequence;  ///< oxford, radiate, boreas
  Recording recording;                               ///< rosbag
  SensorDescription description;                     ///< rosbag
};

namespace {}  // namespace

SensorDescription describedSensors(SensorDescription d, const AutomotiveRunOptions& o, const Settings& given) {
  for (const char* list : {"sequence.filter.invalid_states", "sequence.filter.dyn_props",
                           "sequence.filter.ambig_states", "sequence.filter.doppler_ambig_states"})
    if (const Setting* s = findSetting(given, list))
      throw SettingError(SettingError::Why::NotThisLayout,
                         s->spelled() +
                             ": a recording's detections are kept by its description's keep: lists "
                             "(docs/ros.md), not by the nuScenes reader's");
  if (!o.sequence.reference_channel.empty()) d.reference = o.sequence.reference_channel;
  if (!o.sequence.channels.empty()) {
    std::vector<RadarDescription> kept;
    for (const std::string& name : o.sequence.channels) {
      const auto it = std::find_if(d.radars.begin(), d.radars.end(), [&](const auto& r) { return r.name == name; });
      if (it == d.radars.end())
        throw std::invalid_argument(findSetting(given, "sequence.channels")->spelled() + ": no radar '" + name +
                                    "' in " + d.source);
      kept.push_back(*it);
    }
    d.radars = kept;
  }
  if (findSetting(given, "sequence.filter.max_range"))
    for (auto& r : d.radars) r.fields.max_range = o.sequence.filter.max_range;
  return d;
}

namespace {

/// How a setting the car's sensors need was asked for: as given, or by the method.
std::string askedBy(const Settings& given, const char* path, const std::string& method) {
  const Setting* s = findSetting(given, path);
  return s ? s->spelled() : "method " + method;
}

void openRecording(OdometryRun::Impl& r, const Settings& given) {
  if (r.source.sensors.empty())
    throw std::invalid_argument("format rosbag needs a sensor description (a YAML file, or preset:NAME)");
  r.description = readSensorDescription(r.source.sensors);
  const SensorDescription& d = r.description;
  if (!d.radars.empty() && d.radars[0].kind == RadarKind::Scanning) {  // polar images: the scanning run
    r.kind = PipelineKind::Scanning;
    r.scanning = scanningRunOptions(given, "rosbag");
    r.recording = readRecording("rosbag", r.source.path, d);
    r.name = r.recording.scans->name();
    return;
  }
  if (asksInertial(given)) {  // a 4D radar's 6-DoF run: the rig's radars and its IMU
    r.kind = PipelineKind::Inertial;
    inertialRunOptions(given);  // a bad setting is said before the recording is read
    r.recording = readRecording("rosbag", r.source.path, d);
    r.inertial = inertialRunOptions(given, inertialRunDefaults(d, r.recording.cycles->referenceChannel()));
    if (r.inertial.imu && r.recording.imu.empty())
      throw std::invalid_argument(askedBy(given, "imu", r.inertial.matcher.method) + ": " + r.source.sensors +
                                  (d.imu_topic.empty()
                                       ? " names no imu topic (docs/ros.md)"
                                       : " names " + d.imu_topic + ", but the bag has no message on it"));
    r.name = r.recording.cycles->sceneName();
    return;
  }
  r.automotive = automotiveRunOptions(given);
  r.recording = readRecording("rosbag", r.source.path, describedSensors(d, r.automotive, given));
  const auto& car = r.recording.car;
  const CarSensorOptions& wanted = r.automotive.odometry.car;
  if (wanted.wheels && (!car || car->speed.empty()))
    throw std::invalid_argument(askedBy(given, "odometry.car.wheels", r.automotive.matcher.method) + ": " +
                                r.source.sensors + " names no speed topic (docs/ros.md)");
  if (wanted.gyro && (!car || car->yaw_rate.empty()))
    throw std::invalid_argument(askedBy(given, "odometry.car.gyro", r.automotive.matcher.method) + ": " +
                                r.source.sensors + " names no imu topic (docs/ros.md)");
  if (!wanted.any()) r.recording.car = nullptr;
  r.name = r.recording.cycles->sceneName();
}

void openSequence(OdometryRun::Impl& r, const Settings& given) {
  r.kind = PipelineKind::Scanning;
  // The sequence is read with the settings' reader options; the run takes its radar's defaults.
  const ScanningRunOptions read = scanningRunOptions(given, r.source.format);
  r.sequence =
      std::make_unique<const ScanningSequence>(r.source.path, parseEnum<ScanFormat>(r.source.format), read.sequence);
  r.scanning = scanningRunOptions(given, r.source.format, defaultScanningOptions(*r.sequence));
  r.name = r.sequence->name();
}

}  // namespace

OdometryRun::OdometryRun(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

OdometryRun::OdometryRun(const RunSource& source, const Settings& given) : impl_(std::make_unique<Impl>()) {
  Impl& r = *impl_;
  r.source = source;
  const DatasetFormat format = parseEnum<DatasetFormat>(source.format);
  if (format == DatasetFormat::NuScenes) {
    if (source.scene.empty() || source.scene == "all")
      throw std::invalid_argument("one run is one scene: name it (OdometryRun::openAll opens every scene)");
    r.automotive = automotiveRunOptions(given);
    r.dataset = std::make_shared<const NuScenesDataset>(source.path, source.version);
    r.scene = &r.dataset->scene(source.scene);
    r.name = r.scene->name;
  } else if (format == DatasetFormat::Rosbag) {
    openRecording(r, given);
  } else {
    openSequence(r, given);
  }
}

std::vector<OdometryRun> OdometryRun::openAll(const RunSource& source, const Settings& given) {
  std::vector<OdometryRun> runs;
  if (parseEnum<DatasetFormat>(source.format) != DatasetFormat::NuScenes ||
      !(source.scene.empty() || source.scene == "all")) {
    runs.emplace_back(source, given);
    return runs;
  }
  const AutomotiveRunOptions options = automotiveRunOptions(given);
  const auto dataset = std::make_shared<const NuScenesDataset>(source.path, source.version);
  for (const NuScenesScene& scene : dataset->scenes()) {
    auto impl = std::make_unique<Impl>();
    impl->source = source;
    impl->source.scene = scene.name;
    impl->automotive = options;
    impl->dataset = dataset;
    impl->scene = &scene;
    impl->name = scene.name;
    runs.push_back(OdometryRun(std::move(impl)));
  }
  return runs;
}

OdometryRun::OdometryRun(OdometryRun&&) noexcept = default;
OdometryRun& OdometryRun::operator=(OdometryRun&&) noexcept = default;
OdometryRun::~OdometryRun() = default;

PipelineKind OdometryRun::pipeline() const {
  return impl_->kind;
}
const std::string& OdometryRun::name() const {
  return impl_->name;
}
const RunSource& OdometryRun::source() const {
  return impl_->source;
}

const AutomotiveRunOptions& OdometryRun::automotiveOptions() const {
  if (impl_->kind != PipelineKind::Automotive) throw std::logic_error(impl_->name + ": not an automotive run");
  return impl_->automotive;
}

const ScanningRunOptions& OdometryRun::scanningOptions() const {
  if (impl_->kind != PipelineKind::Scanning) throw std::logic_error(impl_->name + ": not a scanning run");
  return impl_->scanning;
}

const InertialRunOptions& OdometryRun::inertialOptions() const {
  if (impl_->kind != PipelineKind::Inertial) throw std::logic_error(impl_->name + ": not a 6-DoF run");
  return impl_->inertial;
}

bool OdometryRun::hasGroundTruth(std::string* why_not) const {
  const Impl& r = *impl_;
  std::string why;
  bool has = true;
  if (r.sequence) {
    has = r.sequence->hasGroundTruth();
    why = r.source.path +
          " has no ground truth (oxford: gt/radar_odometry.csv; boreas: applanix/radar_poses.csv; radiate has none)";
  } else if (r.recording.scans) {
    has = !r.recording.scans->groundTruth().empty();
    const SensorDescription& d = r.description;
    why = r.name + " has no ground truth (" +
          (d.ground_truth_topic.empty() ? d.source + " names no ground_truth topic"
                                        : "no pose on " + d.ground_truth_topic) +
          ")";
  } else if (r.recording.cycles) {
    has = !r.recording.cycles->groundTruthTrajectory().empty();
    why = r.name + " has no ground truth at the cycles' times";
  }
  if (!has && why_not) *why_not = why;
  return has;
}

AutomotiveRunResult OdometryRun::runAutomotive(const Progress& progress, const StepCallback& on_step) const {
  return runAutomotiveWith(automotiveOptions(), progress, on_step);
}

AutomotiveRunResult OdometryRun::runAutomotiveWith(const AutomotiveRunOptions& o, const Progress& progress,
                                                   const StepCallback& on_step) const {
  const Impl& r = *impl_;
  if (r.scene) return runAutomotiveOdometry(*r.dataset, *r.scene, o, progress, on_step);
  AutomotiveInputs inputs{*r.recording.cycles, r.recording.car, r.recording.problems};
  return runAutomotiveOdometry(inputs, o, makeMatcher(o.matcher), progress, on_step);
}

ScanningRunResult OdometryRun::runScanning(const Progress& progress, const StepCallback& on_step) const {
  const Impl& r = *impl_;
  const ScanningRunOptions& o = scanningOptions();
  const ScanSource& scans = r.sequence ? static_cast<const ScanSource&>(*r.sequence) : *r.recording.scans;
  return runScanningOdometry(scans, o, progress, on_step);
}

InertialRunResult OdometryRun::runInertial(const Progress& progress, const InertialStepCallback& on_step) const {
  const Impl& r = *impl_;
  InertialRunResult out =
      runInertialOdometry(*r.recording.cycles, r.recording.imu, inertialOptions(), progress, on_step);
  out.problems.insert(out.problems.begin(), r.recording.problems.begin(), r.recording.problems.end());
  return out;
}

void runSideBySide(const std::vector<OdometryRun>& runs,
                   const std::function<void(std::size_t, const AutomotiveRunResult&)>& done,
                   const OdometryRun::Progress& progress) {
  if (runs.empty()) return;
  const int threads = detail::resolveThreads(runs[0].automotiveOptions().threads);
  const bool side_by_side = runs.size() > 1 && threads > 1;
  using Indexed = std::pair<std::size_t, AutomotiveRunResult>;
  detail::runOrdered<Indexed>(
      0, runs.size(), side_by_side ? threads : 1,
      [&](std::size_t i) {
        if (!side_by_side) return Indexed(i, runs[i].runAutomotive());
        // The runs, not their cycles, side by side: each on one thread, the same result.
        AutomotiveRunOptions one = runs[i].automotiveOptions();
        one.threads = 1;
        return Indexed(i, runs[i].runAutomotiveWith(one, nullptr, nullptr));
      },
      [&](Indexed& r) {
        done(r.first, r.second);
        if (progress) progress(r.first + 1, runs.size());
      });
}

}  // namespace radar_ndt
