// radar_odometry: radar odometry over a dataset sequence. --format nuscenes: the paper's automotive
// pipeline (Doppler ego-velocity, probabilistic submap of N cycles, weighted NDT) on a nuScenes-
// layout dataroot, or on a recording of point-cloud radars (--format rosbag; a 4D radar's with a
// 6-DoF --method runs the 6-DoF pipeline). --format oxford|radiate|boreas: the scanning pipeline
// (power threshold, weighted NDT against keyframes with the paper's failure handling, motion
// compensation) on scan sequences. Parses options, calls the library, writes and prints; the
// paper's tables are radar_paper_tables.
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
#include "radar_ndt/odometry/local_map_3d.h"
#include "radar_ndt/odometry/matcher_registry.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/odometry_run.h"
#include "radar_ndt/pipeline/scanning_run.h"
#include <pcl/filters/voxel_grid.h>
#include <pcl/io/pcd_io.h>
#ifdef RADAR_NDT_WITH_ROS
#include "radar_ndt/ros/bag_reader.h"
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
  bool planar = false;  ///< 6-DoF runs: projected onto the plane (--planar)
  bool many = false;    ///< several scenes or sequences: file names get the run's name inserted
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
/// gets the metrics when evaluating (with the run's own prior beside them: evaluateRun).
template <typename Run>
json finish(const Run& r, const std::string& name, const Outputs& o, std::optional<EvaluationReport>& report) {
  // A problem of the whole dataset (its can_bus/ folder missing) comes with every scene's run in
  // the same words: said once.
  static std::set<std::string> said;
  for (const auto& p : r.problems)
    if (said.insert(p).second) pcl::console::print_warn("%s: %s\n", name.c_str(), p.c_str());
  if (!o.out.empty()) writeTrajectory(o.fileFor(o.out, name), r.estimate, parseTrajectoryFormat(o.out_format));
  if (!o.steps.empty()) writeFileAtomically(o.fileFor(o.steps, name), stepsCsv(r));
  std::optional<RunEvaluation> evaluation;
  if (o.eval) {
    evaluation = evaluateRun(r, o.metric.empty() ? std::vector<Metric>{} : parseMetrics(o.metric));
    report = evaluation->report;
    if (!o.plot.empty())
      writeEvaluationSvg(o.fileFor(o.plot, name), associate(r.ground_truth, r.estimate), *report,
                         name + " (" + r.method + ")");
  }
  if (!o.json) std::cout << summaryText(r) << (evaluation ? evaluationText(*evaluation) : "");
  const std::string failure = failureText(r);
  if (!failure.empty()) o.failures->push_back(failure);
  return json::parse(evaluation ? summaryJson(r, *evaluation) : summaryJson(r));
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

/// Whether --planar is given to a planar run.
bool planarOnPlanarRun(const po::variables_map& vm, PipelineKind pipeline) {
  return vm["planar"].as<bool>() && pipeline != PipelineKind::Inertial;
}

/// The source the command line names (one scene or every scene, one sequence or several).
std::vector<RunSource> sourcesOf(const po::variables_map& vm) {
  auto text = [&](const char* name) { return vm.count(name) ? vm[name].as<std::string>() : std::string(); };
  const std::string format = vm["format"].as<std::string>();
  if (format == "nuscenes") {
    if (!vm.count("dataroot")) throw std::invalid_argument("--format nuscenes needs --dataroot DIR");
    return {RunSource{format, text("dataroot"), text("scene"), text("version"), ""}};
  }
  if (format == "rosbag") {
    if (!vm.count("bag")) throw std::invalid_argument("--format rosbag needs --bag FILE");
    if (!vm.count("sensors")) throw std::invalid_argument("--format rosbag needs --sensors FILE.yaml (or preset:NAME)");
    return {RunSource{format, text("bag"), "", "", text("sensors")}};
  }
  std::vector<RunSource> out;
  for (const std::string& dir : apps::sequenceDirs(vm)) out.push_back(RunSource{format, dir, "", "", ""});
  return out;
}

/// One run: its maps, the run, its files and summary.
template <typename Result, typename RunIt>
json runOne(const OdometryRun& run, const Outputs& o, bool keyframe_maps, std::vector<EvaluationReport>& reports,
            const RunIt& run_it) {
  std::string why;
  if (o.eval && !run.hasGroundTruth(&why)) throw std::invalid_argument("--eval: " + why);
  RunMaps maps(o, keyframe_maps);
  const Result r = run_it(apps::Progress{o.progress, run.name()}, maps.callback());
  maps.write(o);
  std::optional<EvaluationReport> report;
  json out = finish(r, run.name(), o, report);
  if (report) reports.push_back(*report);
  return out;
}

/// The 6-DoF run's maps: --map, a top view of every scan's detections at its pose (x, y); --map-out,
/// a 3D PCD (x y z intensity = power) of them in the odometry frame, one point a voxel.
struct InertialMaps {
  std::unique_ptr<TopViewMap> top;
  pcl::PointCloud<pcl::PointXYZI>::Ptr points;
  explicit InertialMaps(const Outputs& o) {
    if (!o.map.empty()) top = std::make_unique<TopViewMap>(0.2);
    if (!o.map_out.empty()) points.reset(new pcl::PointCloud<pcl::PointXYZI>);
  }
  InertialStepCallback callback() {
    if (!top && !points) return nullptr;
    return [this](std::size_t, const OdometryStep3D& step, const pcl::PointCloud<PointRadar4D>& body) {
      const pcl::PointCloud<PointRadar4D> world = transformRadar4D(body, step.pose);
      pcl::PointCloud<PointRadar> flat;
      for (const PointRadar4D& p : world) {
        if (points) {
          pcl::PointXYZI q;
          q.x = p.x, q.y = p.y, q.z = p.z, q.intensity = p.power;
          points->push_back(q);
        }
        PointRadar q;
        q.x = p.x, q.y = p.y, q.power = p.power;
        flat.push_back(q);
      }
      if (top) top->add(flat, Pose2::Zero());
    };
  }
  void write(const Outputs& o) const {
    if (top) top->writePng(o.map);
    if (!points) return;
    pcl::PointCloud<pcl::PointXYZI> out;
    if (o.map_voxel > 0 && !points->empty()) {
      pcl::VoxelGrid<pcl::PointXYZI> grid;
      grid.setInputCloud(points);
      const float v = static_cast<float>(o.map_voxel);
      grid.setLeafSize(v, v, v);
      grid.filter(out);
    } else {
      out = *points;
    }
    if (out.empty() || pcl::io::savePCDFileBinary(o.map_out, out) != 0)
      throw std::runtime_error(o.map_out + ": " + (out.empty() ? "no points to write" : "could not be written"));
  }
};

/// One 6-DoF run: its maps, the run (projected onto the plane with --planar), its files and summary.
json runOneInertial(const OdometryRun& run, const Outputs& o, std::vector<EvaluationReport>& reports) {
  std::string why;
  if (o.eval && !run.hasGroundTruth(&why)) throw std::invalid_argument("--eval: " + why);
  InertialMaps maps(o);
  InertialRunResult r = run.runInertial(apps::Progress{o.progress, run.name()}, maps.callback());
  maps.write(o);
  Outputs planar = o;
  if (o.planar) {
    r.estimate = projectToPlane(r.estimate);
    r.ground_truth = projectToPlane(r.ground_truth);
    if (planar.metric.empty()) planar.metric = "1m,kitti,ate";
  }
  std::optional<EvaluationReport> report;
  json out = finish(r, run.name(), planar, report);
  if (report) reports.push_back(*report);
  return out;
}

/// Every run the command line names, through the library's one entry (OdometryRun): nuScenes
/// scenes side by side, sequences one after the other.
int runAll(const po::variables_map& vm, const Outputs& base) {
  const std::vector<RunSource> sources = sourcesOf(vm);
  const PipelineKind pipeline = apps::asksInertial(vm) ? PipelineKind::Inertial : pipelineOf(sources.front());
  const Settings given = pipeline == PipelineKind::Inertial     ? apps::inertialSettings(vm)
                         : pipeline == PipelineKind::Automotive ? apps::automotiveSettings(vm)
                                                                : apps::scanningSettings(vm);
  if (planarOnPlanarRun(vm, pipeline))
    throw std::invalid_argument("--planar takes a 6-DoF run (--format rosbag with --method " + inertialMethodChoices() +
                                ")");
  std::vector<OdometryRun> runs;
  for (const RunSource& source : sources)
    for (OdometryRun& r : OdometryRun::openAll(source, given)) runs.push_back(std::move(r));
  Outputs o = base;
  o.many = runs.size() > 1;
  if (o.many && (!o.map.empty() || !o.map_out.empty()))
    throw std::invalid_argument("--map and --map-out take one --scene or --sequence");
  std::vector<json> summaries;
  std::vector<EvaluationReport> reports;
  if (pipeline == PipelineKind::Automotive && runs.size() > 1) {  // scenes side by side, reported in order
    for (const OdometryRun& r : runs) {
      std::string why;
      if (o.eval && !r.hasGroundTruth(&why)) throw std::invalid_argument("--eval: " + why);
    }
    runSideBySide(
        runs,
        [&](std::size_t i, const AutomotiveRunResult& r) {
          std::optional<EvaluationReport> report;
          summaries.push_back(finish(r, runs[i].name(), o, report));
          if (report) reports.push_back(*report);
        },
        apps::Progress{o.progress, "scenes"});
  } else {
    for (const OdometryRun& run : runs) {
      if (pipeline == PipelineKind::Inertial)
        summaries.push_back(runOneInertial(run, o, reports));
      else if (pipeline == PipelineKind::Automotive)
        summaries.push_back(runOne<AutomotiveRunResult>(
            run, o, false, reports,
            [&](const auto& progress, const auto& cb) { return run.runAutomotive(progress, cb); }));
      else
        summaries.push_back(runOne<ScanningRunResult>(run, o, true, reports, [&](const auto& progress, const auto& cb) {
          return run.runScanning(progress, cb);
        }));
    }
  }
  const char* list = pipeline == PipelineKind::Automotive ? "scenes" : "sequences";
  if (o.json) {
    printJson(summaries, reports, list);
  } else if (reports.size() > 1) {
    std::printf("mean over %zu %s:\n", reports.size(), list);
    std::cout << formatTable(meanReport(reports));
  }
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
    ("planar", po::bool_switch(),
     "6-DoF runs: write and evaluate the trajectory projected onto the plane (x, y, heading; default metrics "
     "1m,kitti,ate), for planar tables")
    ("show-options", po::bool_switch(),
     "print the options the run would use (every field by its path: the defaults for its radar, then the options "
     "given) as JSON, then exit; without a source, the library's defaults")
    ("list-options", "print every pipeline option as a markdown table (the field it sets, its pipeline, meaning "
     "and default), then exit");
  // clang-format on
  return opts;
}

/// The methods the registry of matchers holds, for the usage text: automotive ones, or the ones a
/// scanning radar can run.
std::string methodList(bool scanning) {
  std::string out;
  for (const std::string& name : matcherNames())
    if (!scanning || !findMatcher(name).uses.automotiveOnly()) out += (out.empty() ? "" : "|") + name;
  return out;
}

std::string usage() {
  return "Usage: radar_odometry --format nuscenes --dataroot DIR [--scene NAME|all] [--method " + methodList(false) +
         "]\n"
         "                      [--mode cycle-to-map|paper] [--map-cycles M] [--submap N] [--grid G] [--imu] "
         "[--wheels]\n"
         "                      [--out traj.txt] [--eval] [--metric 1m|kitti|frame|ate|all] [--json] [--plot out.svg]\n"
         "       radar_odometry --format rosbag --bag FILE --sensors FILE.yaml|preset:NAME [the options of its radar's "
         "pipeline]\n"
         "       radar_odometry --format rosbag --bag FILE --sensors FILE.yaml|preset:NAME --method " +
         inertialMethodChoices() +
         "\n"
         "                      [--imu] [--radar-latency S] [--planar] [--out traj.txt] [--eval] [--map-out map.pcd]  "
         "(a 4D radar: 6-DoF)\n"
         "       radar_odometry --format oxford|radiate|boreas --sequence DIR... [--method " +
         methodList(true) +
         "] [--grid G]\n"
         "                      [--threshold T] [--power-shift S] [--points cartesian|polar] [--imu] [--out traj.txt]\n"
         "                      [--eval] [--json] [--plot out.svg] [--map top.png]\n"
         "       radar_odometry --format F [a source] [options] --show-options   (the options a run would use, as "
         "JSON)\n"
         "nuscenes: one pose per radar cycle (one sweep of every radar, clocked by the reference radar), the\n"
         "vehicle frame at the reference sweep's timestamp; each cycle matched to a local map of the M cycles before "
         "it\n"
         "from the Doppler ego-motion and fused with it (paper mode: submap of N cycles to the last submap, not "
         "fused).\n"
         "Unreadable sweeps are reported and left out of their cycle.\n"
         "oxford|radiate|boreas: one pose per scan, the vehicle at the scan's timestamp (oxford: the first azimuth's;\n"
         "boreas: the middle one's, as the dataset names its scans); each scan\n"
         "motion-compensated and matched to the last keyframe from a constant-velocity guess, failures retried with\n"
         "the grid enlarged, then with s halved. Unreadable scans are reported and bridged with the motion model;\n"
         "bad index lines are reported and left out.\n"
         "6-DoF (a 4D radar's recording and a 6-DoF --method): one pose per scan of one radar, the rig's frame,\n"
         "z and the full rotation; each scan matched to a local map of recent keyframes from the prior (--imu: the\n"
         "inertial filter; else the last turn rate and the Doppler velocity); doppler-imu integrates the IMU and the\n"
         "Doppler velocity, no matching.\n"
         "A run whose steps were mostly not matched (too few points, fallbacks, unreadable files) says so in its\n"
         "last line and exits with code 1. Every option: docs/apps.md.";
}

nlohmann::ordered_json toJson(const FieldValue& v) {
  switch (v.kind()) {
    case FieldValue::Kind::Bool: return v.boolean();
    case FieldValue::Kind::Integer: return v.integer();
    case FieldValue::Kind::Real: return v.real();
    case FieldValue::Kind::Text: return v.text();
    default: {
      nlohmann::ordered_json list = nlohmann::ordered_json::array();
      for (const FieldValue& item : v.list()) list.push_back(toJson(item));
      return list;
    }
  }
}

/// --show-options: the options a run would use, every field by its path, as JSON. With a source,
/// opened (the defaults for its radar, a recording's pipeline); without, the library's defaults.
int showOptions(const po::variables_map& vm) {
  const std::string format = vm["format"].as<std::string>();
  const bool has_source = vm.count("dataroot") || vm.count("sequence") || vm.count("bag");
  nlohmann::ordered_json out = nlohmann::ordered_json::object();  // in the tables' order
  auto add = [&out](const auto& options) {
    for (const auto& [path, value] : fieldValues(options)) out[path] = toJson(value);
  };
  if (has_source) {
    RunSource source = sourcesOf(vm).front();
    const PipelineKind pipeline = apps::asksInertial(vm) ? PipelineKind::Inertial : pipelineOf(source);
    if (pipeline == PipelineKind::Automotive && source.format == "nuscenes" &&
        (source.scene == "all" || source.scene.empty()))
      source.scene = NuScenesDataset(source.path, source.version).scenes().at(0).name;
    const OdometryRun run(source, pipeline == PipelineKind::Inertial     ? apps::inertialSettings(vm)
                                  : pipeline == PipelineKind::Automotive ? apps::automotiveSettings(vm)
                                                                         : apps::scanningSettings(vm));
    if (pipeline == PipelineKind::Inertial)
      add(run.inertialOptions());
    else if (pipeline == PipelineKind::Automotive)
      add(run.automotiveOptions());
    else
      add(run.scanningOptions());
  } else if (format == "rosbag") {
    throw std::invalid_argument("--show-options with --format rosbag needs --bag and --sensors");
  } else if (apps::pipelineOf(format) == apps::Pipeline::Automotive) {
    add(automotiveRunOptions(apps::automotiveSettings(vm)));
  } else {
    add(scanningRunOptions(apps::scanningSettings(vm), format));
  }
  std::cout << out.dump(1) << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string(argv[1]) == "--list-options") {
    std::printf("%s", apps::pipelineOptionsMarkdown().c_str());
    return 0;
  }
  const po::options_description opts = odometryOptions();
  po::variables_map vm;
  const int rc = apps::parseCommandLine(argc, argv, opts, usage(), vm);
  if (rc >= 0) return rc;

#ifdef RADAR_NDT_WITH_ROS
  ros1::registerBagReader();
#endif
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
    o.planar = vm["planar"].as<bool>();
    o.progress = !vm["quiet"].as<bool>() && isatty(STDERR_FILENO);
    parseTrajectoryFormat(o.out_format);  // a bad value fails before the run
    if (!o.metric.empty()) parseMetrics(o.metric);
    if (!(o.map_voxel >= 0)) throw std::invalid_argument("--map-voxel must be >= 0 (m)");
    if (vm["show-options"].as<bool>()) return showOptions(vm);
    return runAll(vm, o);
  });
}
