// radar_odometry: radar odometry over a dataset sequence. --format nuscenes: the paper's automotive
// pipeline (Doppler ego-velocity, probabilistic submap of N cycles, weighted NDT) on a nuScenes-
// layout dataroot. --format oxford|radiate|boreas: the scanning pipeline (power threshold, weighted NDT
// against keyframes with the paper's failure handling, motion compensation) on scan sequences.
// Parses options, calls the library, writes and prints; the paper's tables are radar_paper_tables.
#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>
#include <set>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "app_common.h"
#include "pipeline_options.h"
#include "radar_ndt/evaluation/point_map.h"
#include "radar_ndt/evaluation/report.h"
#include "radar_ndt/evaluation/run_report.h"
#include "radar_ndt/evaluation/svg_plot.h"
#include "radar_ndt/evaluation/top_view_map.h"
#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/scanning_run.h"
#ifdef RADAR_NDT_WITH_ROS
#include "radar_ndt/ros/rosbag_scans.h"
#include "radar_ndt/ros/rosbag_sequence.h"
#endif

using namespace radar_ndt;
namespace po = boost::program_options;
using nlohmann::json;

namespace {

/// What to write and print, the same for both pipelines.
struct Outputs {
  std::string out, out_format, steps, plot, map, map_out, metric;
  double map_voxel = 0.2;
  bool eval = false, json = false, progress = false;
  bool many = false;  ///< several scenes or sequences: file names get the run's name inserted
  /// The failure lines of runs mostly not matched (failureText), printed last; the exit code is 1.
  std::shared_ptr<std::vector<std::string>> failures = std::make_shared<std::vector<std::string>>();
  /// `path` for run `name`: as given for one run, else NAME inserted before the extension.
  std::string fileFor(const std::string& path, const std::string& name) const {
    if (!many) return path;
    const auto dot = path.find_last_of('.'), slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + "_" + name;
    return path.substr(0, dot) + "_" + name + path.substr(dot);
  }
};

/// Writes the run's files, prints its summary (unless JSON) and returns its JSON summary; `report`
/// gets the metrics when evaluating.
template <typename Run>
json finish(const Run& r, const std::string& name, const Outputs& o, std::optional<EvaluationReport>& report) {
  // A problem of the whole dataset (its can_bus/ folder missing) comes with every scene's run in
  // the same words: said once.
  static std::set<std::string> said;
  for (const auto& p : r.problems)
    if (said.insert(p).second) pcl::console::print_warn("%s: %s\n", name.c_str(), p.c_str());
  if (!o.out.empty()) writeTrajectory(o.fileFor(o.out, name), r.estimate, parseTrajectoryFormat(o.out_format));
  if (!o.steps.empty()) writeFileAtomically(o.fileFor(o.steps, name), stepsCsv(r));
  if (o.eval) {
    const PosePairs pairs = associate(r.ground_truth, r.estimate);
    report = evaluate(pairs, o.metric.empty() ? defaultMetrics(r) : parseMetrics(o.metric));
    if (!o.plot.empty()) writeEvaluationSvg(o.fileFor(o.plot, name), pairs, *report, name + " (" + r.method + ")");
  }
  // Beside the method, its own prior: each step's initial guess judged as its match is.
  const FrameError prior = o.eval ? priorFrameError(r.steps, r.ground_truth) : FrameError{};
  const char* prior_label = r.prior.c_str();
  if (!o.json) {
    std::cout << summaryText(r);
    if (report) std::cout << formatTable(*report) << priorText(prior, prior_label);
  }
  const std::string failure = failureText(r);
  if (!failure.empty()) o.failures->push_back(failure);
  json out = json::parse(summaryJson(r, report ? &*report : nullptr));
  if (prior.pairs > 0)
    out["prior_frame"] = {{"prior", prior_label},
                          {"trans_err_m", prior.trans_err_m},
                          {"rot_err_deg", prior.rot_err_deg},
                          {"pairs", prior.pairs}};
  return out;
}

/// One JSON object for one run; for several, {"runs": [...], "mean": {"metrics": ...}} under the
/// key `list` ("scenes" or "sequences").
void printJson(const std::vector<json>& runs, const std::vector<EvaluationReport>& reports, const char* list) {
  if (runs.size() == 1) {
    std::cout << runs[0].dump(2) << std::endl;
    return;
  }
  json mean = json::object();
  // Each error averaged over the runs where it is defined (null: none), counts summed.
  if (!reports.empty()) mean["metrics"] = json::parse(metricsJson(meanReport(reports)));
  std::cout << json{{list, runs}, {"mean", mean}}.dump(2) << std::endl;
}

/// The failure lines, last (stderr with --json, which keeps stdout JSON): exit code 1 when any.
int reportFailures(const Outputs& o) {
  std::cout << std::flush;
  for (const auto& f : *o.failures) (o.json ? std::cerr : std::cout) << f;
  return o.failures->empty() ? 0 : 1;
}

/// The maps a run asks for (--map: a top-view PNG; --map-out: a PCD of the points in the world
/// frame) and the callback that fills them: every cycle's (moving detections removed), or every
/// keyframe scan's. Written by write().
struct RunMaps {
  std::unique_ptr<TopViewMap> top;
  std::unique_ptr<PointMap> points;
  bool keyframes_only = false;
  RunMaps(const Outputs& o, bool keyframes) : keyframes_only(keyframes) {
    if (!o.map.empty()) top = std::make_unique<TopViewMap>(0.2);
    if (!o.map_out.empty()) points = std::make_unique<PointMap>(o.map_voxel);
  }
  bool any() const { return top || points; }
  std::function<void(std::size_t, const OdometryStep&, const pcl::PointCloud<PointRadar>&)> callback() {
    if (!any()) return nullptr;
    return [this](std::size_t k, const OdometryStep& step, const pcl::PointCloud<PointRadar>& cloud) {
      if (top) top->add(cloud, step.pose);
      if (points && (!keyframes_only || step.keyframe || k == 0)) points->add(cloud, step.pose);
    };
  }
  void write(const Outputs& o) const {
    if (top) top->writePng(o.map);
    if (points) points->write(o.map_out);
  }
};

int runAutomotive(const po::variables_map& vm, const Outputs& base) {
  const AutomotiveRunOptions options = apps::automotiveOptions(vm);
  const NuScenesDataset dataset = apps::openDataset(vm);
  const std::vector<const NuScenesScene*> scenes = apps::selectScenes(dataset, vm);
  Outputs o = base;
  o.many = scenes.size() > 1;
  std::vector<json> runs;
  std::vector<EvaluationReport> reports;
  auto finishScene = [&](std::size_t i, const AutomotiveRunResult& r) {
    std::optional<EvaluationReport> report;
    runs.push_back(finish(r, scenes[i]->name, o, report));
    if (report) reports.push_back(*report);
  };
  RunMaps maps(o, false);
  if (maps.any() && scenes.size() > 1) throw std::invalid_argument("--map and --map-out take one --scene");
  if (scenes.size() == 1) {  // one scene: its cycles on the pipeline, with a progress bar
    finishScene(0, runAutomotiveOdometry(dataset, *scenes[0], options, apps::Progress{o.progress, scenes[0]->name},
                                         maps.callback()));
    maps.write(o);
  } else {  // several: the scenes side by side, reported in order
    runAutomotiveScenes(dataset, scenes, options, finishScene, apps::Progress{o.progress, "scenes"});
  }
  if (o.json) {
    printJson(runs, reports, "scenes");
  } else if (reports.size() > 1) {
    std::printf("mean over %zu scenes:\n", reports.size());
    std::cout << formatTable(meanReport(reports));
  }
  return reportFailures(o);
}

/// The sensor description with the command line's nuScenes-style sequence options applied to it:
/// the reference radar, the radars used, the range.
SensorDescription describedSensors(const po::variables_map& vm, const AutomotiveRunOptions& options) {
  if (!vm.count("sensors")) throw std::invalid_argument("--format rosbag needs --sensors FILE.yaml (or preset:NAME)");
  SensorDescription d = readSensorDescription(vm["sensors"].as<std::string>());
  if (!options.sequence.reference_channel.empty()) d.reference = options.sequence.reference_channel;
  if (!options.sequence.channels.empty()) {
    std::vector<RadarDescription> kept;
    for (const std::string& name : options.sequence.channels) {
      const auto it = std::find_if(d.radars.begin(), d.radars.end(), [&](const auto& r) { return r.name == name; });
      if (it == d.radars.end()) throw std::invalid_argument("--channels: no radar '" + name + "' in " + d.source);
      kept.push_back(*it);
    }
    d.radars = kept;
  }
  if (vm.count("max-range"))
    for (auto& r : d.radars) r.fields.max_range = options.sequence.filter.max_range;
  return d;
}

#ifdef RADAR_NDT_WITH_ROS
/// A scanning radar's bag: the scanning pipeline, with its options (the description's one radar).
int runScanningBag(const po::variables_map& vm, const Outputs& o, const SensorDescription& d) {
  const ScanningRunOptions options = apps::scanningOptions(vm);
  const ros1::RosbagScanSequence bag(vm["bag"].as<std::string>(), d);
  if (o.eval && bag.groundTruth().empty())
    throw std::invalid_argument("--eval: " + bag.name() + " has no ground truth (" +
                                (d.ground_truth_topic.empty() ? d.source + " names no ground_truth topic"
                                                              : "no pose on " + d.ground_truth_topic) +
                                ")");
  RunMaps maps(o, true);
  const ScanningRunResult r =
      runScanningOdometry(bag, options, apps::Progress{o.progress, bag.name()}, maps.callback());
  maps.write(o);
  std::optional<EvaluationReport> report;
  const json run = finish(r, bag.name(), o, report);
  if (o.json) printJson({run}, {}, "sequences");
  return reportFailures(o);
}

int runRosbag(const po::variables_map& vm, const Outputs& o) {
  if (!vm.count("bag")) throw std::invalid_argument("--format rosbag needs --bag FILE");
  if (!vm.count("sensors")) throw std::invalid_argument("--format rosbag needs --sensors FILE.yaml (or preset:NAME)");
  const SensorDescription described = readSensorDescription(vm["sensors"].as<std::string>());
  if (!described.radars.empty() && described.radars[0].kind == RadarKind::Scanning)
    return runScanningBag(vm, o, described);
  const AutomotiveRunOptions options = apps::automotiveOptions(vm);
  const ros1::RosbagRadarSequence bag(vm["bag"].as<std::string>(), describedSensors(vm, options));
  AutomotiveInputs inputs{bag, bag.vehicleSignals(), bag.problems()};
  if (options.odometry.car.wheels && (!inputs.car || inputs.car->speed.empty()))
    throw std::invalid_argument("--wheels: " + vm["sensors"].as<std::string>() +
                                " names no speed topic (docs/ros.md); --imu fuses the gyro");
  if (options.odometry.car.gyro && (!inputs.car || inputs.car->yaw_rate.empty()))
    throw std::invalid_argument("--imu: " + vm["sensors"].as<std::string>() + " names no imu topic");
  if (!options.odometry.car.any()) inputs.car = nullptr;
  if (o.eval && bag.groundTruthTrajectory().empty())
    throw std::invalid_argument("--eval: " + bag.sceneName() + " has no ground truth at the cycles' times");
  const AutomotiveRunResult r =
      runAutomotiveOdometry(inputs, options, makeMatcher(options.matcher), apps::Progress{o.progress, bag.sceneName()});
  std::optional<EvaluationReport> report;
  const json run = finish(r, bag.sceneName(), o, report);
  if (o.json) printJson({run}, {}, "scenes");
  return reportFailures(o);
}
#else
int runRosbag(const po::variables_map&, const Outputs&) {
  throw std::invalid_argument(
      "--format rosbag: this build has no ROS support (Debian's ROS 1 was not found: bash .ci/deps)");
}
#endif

int runScanning(const po::variables_map& vm, const Outputs& base) {
  const std::vector<std::string> dirs = apps::sequenceDirs(vm);
  const ScanFormat format = parseEnum<ScanFormat>(vm["format"].as<std::string>());
  Outputs o = base;
  o.many = dirs.size() > 1;
  if (o.many && (!o.map.empty() || !o.map_out.empty()))
    throw std::invalid_argument("--map and --map-out take one --sequence");
  std::vector<json> runs;
  std::vector<EvaluationReport> reports;
  for (const std::string& dir : dirs) {
    const ScanningSequence sequence(dir, format, apps::scanningOptions(vm).sequence);
    // The command line over the defaults for this sequence's radar.
    const ScanningRunOptions options = apps::scanningOptions(vm, defaultScanningOptions(sequence));
    if (o.eval && !sequence.hasGroundTruth())
      throw std::invalid_argument(
          "--eval: " + dir +
          " has no ground truth (oxford: gt/radar_odometry.csv; boreas: applanix/radar_poses.csv; "
          "radiate has none)");
    RunMaps maps(o, true);
    const ScanningRunResult r =
        runScanningOdometry(sequence, options, apps::Progress{o.progress, sequence.name()}, maps.callback());
    maps.write(o);
    std::optional<EvaluationReport> report;
    runs.push_back(finish(r, sequence.name(), o, report));
    if (report) reports.push_back(*report);
  }
  if (o.json) printJson(runs, reports, "sequences");
  return reportFailures(o);
}

po::options_description odometryOptions() {
  po::options_description opts("Options");
  opts.add_options()("help,h", "print this help and exit");
  apps::addPipelineOptions(opts);
  // clang-format off
  opts.add_options()
    ("out", po::value<std::string>(),
     "write the trajectory here (several scenes or sequences: one file each, NAME inserted before the extension)")
    ("out-format", po::value<std::string>()->default_value("tum"), "kitti | tum (TUM keeps the cycle timestamps) | boreas (the Boreas odometry leaderboard's: µs and "
     "T_rk_r0 in the radar's axes, x forward, y right, z down)")
    ("steps", po::value<std::string>(),
     "write one CSV line per cycle or scan: status, attempts, grid, motion, initial guess, points "
     "(nuscenes: and the ground-truth motion)")
    ("eval", po::bool_switch(),
     "compare with the ground truth (nuscenes: the scene's ego poses; oxford: gt/radar_odometry.csv)")
    ("metric", po::value<std::string>(),
     "with --eval: kitti|1m|frame|ate|all, or a list; default 1m (nuscenes), kitti,frame (scanning)")
    ("json", po::bool_switch(),
     "print one JSON object (summary, and with --eval a \"metrics\" entry shaped as radar_eval's; several "
     "runs: {\"scenes\"|\"sequences\": [...], \"mean\": {\"metrics\": ...}})")
    ("plot", po::value<std::string>(), "with --eval: SVG of estimate vs ground truth (one per scene or sequence)")
    ("map", po::value<std::string>(),
     "write a top-view PNG of all scans or cycles at their estimated poses (0.2 m/pixel; one --sequence or --scene)")
    ("map-out", po::value<std::string>(),
     "write the map as a PCD in the first pose's frame: the keyframe scans' points (scanning) or every "
     "cycle's stationary detections (automotive), one point a voxel (one --sequence or --scene)")
    ("map-voxel", po::value<double>()->default_value(0.2), "--map-out: the voxel's side (m); 0: every point")
    ("list-options", "print every pipeline option as a markdown table (the field it sets, its pipeline, meaning "
     "and default), then exit");
  // clang-format on
  return opts;
}

const char* const kUsage =
    "Usage: radar_odometry --format nuscenes --dataroot DIR [--scene NAME|all] [--method "
    "pw-ndt|pcl-ndt|pcl-icp|doppler|rapp-ndt]\n"
    "                      [--mode cycle-to-map|paper] [--map-cycles M] [--submap N] [--grid G] [--out traj.txt] "
    "[--eval]\n"
    "                      [--metric 1m|kitti|frame|ate|all] [--json] [--plot out.svg]\n"
    "       radar_odometry --format rosbag --bag FILE --sensors FILE.yaml|preset:NAME [the nuscenes options]\n"
    "       radar_odometry --format oxford|radiate|boreas --sequence DIR... [--method pw-ndt|pcl-ndt|pcl-icp] "
    "[--grid G]\n"
    "                      [--threshold T] [--power-shift S] [--points cartesian|polar] [--out traj.txt] [--eval] "
    "[--json]\n"
    "                      [--plot out.svg] [--map top.png]\n"
    "nuscenes: one pose per radar cycle (one sweep of every radar, clocked by the reference radar), the\n"
    "vehicle frame at the reference sweep's timestamp; each cycle matched to a local map of the M cycles before it\n"
    "from the Doppler ego-motion and fused with it (paper mode: submap of N cycles to the last submap, not fused).\n"
    "Unreadable sweeps are reported and left out of their cycle.\n"
    "oxford|radiate|boreas: one pose per scan, the vehicle at the scan's timestamp (oxford: the first azimuth's;\n"
    "boreas: the middle one's, as the dataset names its scans); each scan\n"
    "motion-compensated and matched to the last keyframe from a constant-velocity guess, failures retried with\n"
    "the grid enlarged, then with s halved. Unreadable scans are reported and bridged with the motion model;\n"
    "bad index lines are reported and left out.\n"
    "A run whose steps were mostly not matched (too few points, fallbacks, unreadable files) says so in its\n"
    "last line and exits with code 1. Every option: docs/apps.md.";

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "--list-options") {
    std::printf("%s", apps::pipelineOptionsMarkdown().c_str());
    return 0;
  }
  const po::options_description opts = odometryOptions();
  po::variables_map vm;
  const int rc = apps::parseCommandLine(argc, argv, opts, kUsage, vm);
  if (rc >= 0) return rc;

  return apps::runGuarded("radar_odometry", [&]() {
    Outputs o;
    auto text = [&](const char* name) { return vm.count(name) ? vm[name].as<std::string>() : std::string(); };
    o.out = text("out");
    o.out_format = text("out-format");
    o.steps = text("steps");
    o.plot = text("plot");
    o.map = text("map");
    o.map_out = text("map-out");
    o.map_voxel = vm["map-voxel"].as<double>();
    o.metric = text("metric");
    o.eval = vm["eval"].as<bool>();
    o.json = vm["json"].as<bool>();
    o.progress = !vm["quiet"].as<bool>() && isatty(STDERR_FILENO);
    parseTrajectoryFormat(o.out_format);  // a bad value fails before the run
    if (!o.metric.empty()) parseMetrics(o.metric);
    if (!(o.map_voxel >= 0)) throw std::invalid_argument("--map-voxel must be >= 0 (m)");
    if (vm["format"].as<std::string>() == "rosbag") return runRosbag(vm, o);
    return apps::pipelineOf(vm["format"].as<std::string>()) == apps::Pipeline::Automotive ? runAutomotive(vm, o)
                                                                                          : runScanning(vm, o);
  });
}
