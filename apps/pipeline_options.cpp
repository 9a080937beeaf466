#include "pipeline_options.h"

#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace radar_ndt {
namespace apps {

namespace po = boost::program_options;

namespace {
std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace

Pipeline pipelineOf(const std::string& format) {
  if (format == "nuscenes") return Pipeline::Automotive;
  if (format == "oxford" || format == "radiate" || format == "boreas") return Pipeline::Scanning;
  throw std::invalid_argument("--format " + format + " is not supported (nuscenes, oxford, radiate, boreas)");
}

void addPipelineOptions(po::options_description& opts) {
  // Every default in the help is the library's own.
  const AutomotiveRunOptions a;
  const ScanningRunOptions s;
  // clang-format off
  opts.add_options()
    ("format", po::value<std::string>()->required(),
     "dataset layout: nuscenes (automotive) | oxford | radiate | boreas (scanning)")
    ("dataroot", po::value<std::string>(), "nuscenes: the dataroot (holds v1.0-*/, samples/, sweeps/)")
    ("sequence", po::value<std::vector<std::string>>()->multitoken(),
     "oxford: a directory with radar.timestamps, radar/<stamp>.png and optionally "
     "gt/radar_odometry.csv; radiate: one with Navtech_Polar.txt and Navtech_Polar/<frame>.png; boreas: "
     "one with radar/<stamp>.png and optionally applanix/radar_poses.csv")
    ("version", po::value<std::string>()->default_value(""),
     "nuscenes: table folder under dataroot (default: the one holding sensor.json)")
    ("scene", po::value<std::string>()->default_value("all"),
     "nuscenes: scene name, or 'all' (each scene, then the mean)")
    ("method", po::value<std::string>()->default_value("pw-ndt"),
     "pw-ndt (ours) | pcl-ndt | pcl-icp | doppler (Kellner's ego-velocity "
     "integration, nuscenes) | rapp-ndt (Doppler-weighted grid NDT, nuscenes)")
    ("grid", po::value<double>(),
     ("NDT grid size g (m), default " + num(a.odometry.grid) + " (nuscenes) or " + num(s.odometry.grid) +
     " (scanning); pcl-icp: max correspondence distance").c_str())
    ("no-gate", po::bool_switch(),
     "accept every converged match: no motion-prior (nor, nuscenes, Doppler chi-square) check (ablation)")
    ("max-cycles", po::value<std::size_t>(), "stop after this many cycles per scene, or scans (default: all)")
    ("max-range", po::value<double>(),
     ("nuscenes: drop detections beyond this range (m), default " + num(a.sequence.filter.max_range) +
     "; scanning: front-end range limit, default " + num(s.front_end.max_range)).c_str())
    ("mode", po::value<std::string>(),
     (std::string("nuscenes: cycle-to-map (the newest cycle to a local map of earlier cycles, fused with the "
     "Doppler motion) | paper (submap to submap, not fused: the paper's scheme); default ") +
     toString(a.odometry.mode)).c_str())
    ("submap", po::value<std::size_t>(),
     ("nuscenes, paper mode: N, radar cycles per submap (default " +
      num(static_cast<double>(a.odometry.submap_size)) + ")").c_str())
    ("map-cycles", po::value<std::size_t>(), ("nuscenes, cycle-to-map: M, earlier cycles in the local map (default " +
                                              num(static_cast<double>(a.odometry.map_cycles)) + ")").c_str())
    ("no-fusion", po::bool_switch(),
     "nuscenes: the accepted match is the motion, not fused with the Doppler motion (ablation; paper mode never fuses)")
    ("covariance", po::value<std::string>(),
     "nuscenes: point covariance: polar (ARS408 range/azimuth spec, default) | rms (reported x_rms/y_rms)")
    ("reference-channel", po::value<std::string>(),
     "nuscenes: radar channel that clocks the cycles (default: the forward-facing one)")
    ("channels", po::value<std::string>(),
     "nuscenes: comma-separated radar channels to use (default: every radar in sensor.json); one "
     "channel runs a one-radar car")
    ("doppler-threshold", po::value<double>(),
     ("nuscenes: ego-velocity RANSAC inlier and moving-detection threshold on |Doppler − "
     "predicted| (m/s), default " + num(a.front_end.ego_velocity.inlier_threshold)).c_str())
    ("lateral-sigma", po::value<double>(),
     ("nuscenes: ego-velocity: σ (m/s) of the prior vy = 0 at the vehicle origin (nuScenes: the rear "
     "axle), default " + num(a.front_end.ego_velocity.lateral_sigma) + "; 0: none, the plain 3-DoF fit").c_str())
    ("ego-model", po::value<std::string>(),
     "nuscenes: ego-velocity model: auto (default: full when radars sit at two places or more, else "
     "nonholonomic) | full (vx, vy, yaw rate) | nonholonomic (vy = 0: one radar suffices)")
    ("no-time-compensation", po::bool_switch(),
     "nuscenes: do not move each radar's sweep to the reference time (ablation)")
    ("keep-moving", po::bool_switch(),
     "nuscenes: do not remove detections that disagree with the Doppler ego-velocity (ablation)")
    ("start", po::value<std::size_t>(), "scanning: first scan used (default 0)")
    ("threshold", po::value<double>(),
     ("scanning: power threshold (0..1) of the front-end, default " + num(s.front_end.threshold) + " (boreas scans "
     "with chirp types: " + num(kBoreasChirpThreshold) + ")").c_str())
    ("power-shift", po::value<double>(), ("scanning, pw-ndt: power shift s of the weights max(p - s, 0), default " +
                                          num(s.odometry.power_shift) + " (boreas scans with chirp types: " +
                                          num(kBoreasChirpThreshold) + "); 0 turns it off").c_str())
    ("no-source-shift", po::bool_switch(),
     "scanning, pw-ndt: shift the cells' weights (eq. 1) only; the matching weights are "
     "p·exp(-(σx+σy)/2) (ablation; the paper shifts both)")
    ("points", po::value<std::string>(),
     "scanning: cartesian (the paper's image, default) | polar (one point per cell)")
    ("pixel", po::value<double>(),
     ("scanning, cartesian: metres per pixel, default " + num(s.front_end.cartesian_resolution)).c_str())
    ("bin-size", po::value<double>(),
     ("oxford: range bin size (m), default " + num(s.sequence.oxford.convention.range_resolution) +
     " (the dataset's figure; its SDK uses 0.0432); boreas: default by the scan's date as the SDK decides "
     "(" + num(kBoreasBinBeforeUpgrade) + " before 2021-09-21, " + num(kBoreasBinAfterUpgrade) + " after)").c_str())
    ("bins", po::value<int>(),
     ("oxford: range bins a PNG row must have after its 11 metadata bytes, default " +
     num(s.sequence.oxford.expected_bins) + " (the CTS350-X's); 0 accepts any width; boreas: default any").c_str())
    ("keyframe-distance", po::value<double>(),
     ("scanning: match to a keyframe replaced after this many metres (or " +
     num(s.odometry.keyframes.rotation) + " rad, or a failed match), default " +
     num(s.odometry.keyframes.distance) + "; 0: scan to scan as the paper").c_str())
    ("no-chirp-correction", po::bool_switch(),
     "scanning: leave the up/down-chirp range shifts of scans with chirp types (boreas, 2024) as they are")
    ("no-motion-compensation", po::bool_switch(),
     "scanning: do not move points to the scan's reference time (ablation)")
    ("compensation", po::value<std::string>(),
     ("scanning: how the source's sweep is de-skewed: rounds (with the velocity of the step before, "
     "re-estimated between matches) or joint (inside the match, by the motion being estimated; "
     "pw-ndt only), default " + std::string(toString(s.odometry.compensation.mode))).c_str())
    ("compensation-rounds", po::value<int>(), ("scanning: matches per scan at most, the velocity of the points' motion "
                                               "compensation re-estimated between them, default " +
                                               std::to_string(s.odometry.compensation.max_rounds)).c_str())
    ("compensation-tolerance", po::value<double>(),
     ("scanning: another compensation round only when the match moved the "
     "velocity by more (m/s; yaw rate x 10 m), default " +
     num(s.odometry.compensation.tolerance)).c_str())
    ("threads", po::value<int>(), "threads: the next scans (cycles) read and through the front-end on the others "
                                  "while one is matched, several nuScenes scenes side by side (outputs identical "
                                  "for any number), default 0: every core; 1: one thread")
    ("no-prefetch", po::bool_switch(), "the same as --threads 1")
    ("quiet,q", po::bool_switch(), "no progress bar");
  // clang-format on
}

AutomotiveRunOptions automotiveOptions(const po::variables_map& vm) {
  auto has = [&](const char* name) { return vm.count(name) > 0; };
  AutomotiveRunOptions o;
  if (has("reference-channel")) o.sequence.reference_channel = vm["reference-channel"].as<std::string>();
  if (has("channels")) {
    std::stringstream list(vm["channels"].as<std::string>());  // "A,B" or "A, B"
    for (std::string name; std::getline(list, name, ',');) {
      const std::size_t b = name.find_first_not_of(' ');
      if (b != std::string::npos) o.sequence.channels.push_back(name.substr(b, name.find_last_not_of(' ') - b + 1));
    }
  }
  if (has("max-range")) o.sequence.filter.max_range = vm["max-range"].as<double>();
  if (has("covariance")) o.front_end.covariance_model = parsePointCovarianceModel(vm["covariance"].as<std::string>());
  o.front_end.compensate_time = !vm["no-time-compensation"].as<bool>();
  if (has("doppler-threshold")) o.front_end.ego_velocity.inlier_threshold = vm["doppler-threshold"].as<double>();
  if (has("lateral-sigma")) o.front_end.ego_velocity.lateral_sigma = vm["lateral-sigma"].as<double>();
  if (has("ego-model")) o.front_end.ego_velocity.model = parseEgoVelocityModel(vm["ego-model"].as<std::string>());
  o.front_end.remove_moving = !vm["keep-moving"].as<bool>();
  if (has("mode") && parseAutomotiveMatchMode(vm["mode"].as<std::string>()) == AutomotiveMatchMode::SubmapToSubmap)
    o.odometry = o.odometry.paper(o.odometry.submap_size);
  if (has("submap")) o.odometry.submap_size = vm["submap"].as<std::size_t>();
  if (has("map-cycles")) o.odometry.map_cycles = vm["map-cycles"].as<std::size_t>();
  if (vm["no-fusion"].as<bool>()) o.odometry.fuse_doppler = false;
  o.odometry.gate.enabled = !vm["no-gate"].as<bool>();
  if (has("grid")) o.odometry.grid = vm["grid"].as<double>();
  if (has("max-cycles")) o.max_cycles = vm["max-cycles"].as<std::size_t>();
  if (has("threads")) o.threads = vm["threads"].as<int>();
  if (vm["no-prefetch"].as<bool>()) o.threads = 1;
  o = withMethod(o, parseMethod(vm["method"].as<std::string>()));
  o.validate();
  return o;
}

ScanningRunOptions scanningOptions(const po::variables_map& vm, const ScanningRunOptions& base) {
  auto has = [&](const char* name) { return vm.count(name) > 0; };
  ScanningRunOptions o = base;
  o.matcher.method = parseMethod(vm["method"].as<std::string>());
  auto& od = o.odometry;
  if (has("grid")) od.grid = vm["grid"].as<double>();
  if (has("power-shift")) od.power_shift = static_cast<float>(vm["power-shift"].as<double>());
  od.compensation.enabled = !vm["no-motion-compensation"].as<bool>();
  if (has("compensation")) od.compensation.mode = parseCompensationMode(vm["compensation"].as<std::string>());
  if (has("compensation-rounds")) od.compensation.max_rounds = vm["compensation-rounds"].as<int>();
  if (has("compensation-tolerance")) od.compensation.tolerance = vm["compensation-tolerance"].as<double>();
  od.shift_source_weights = !vm["no-source-shift"].as<bool>();
  if (vm["no-chirp-correction"].as<bool>()) o.chirp.enabled = false;
  if (has("keyframe-distance")) od.keyframes.distance = vm["keyframe-distance"].as<double>();
  od.gate.enabled = !vm["no-gate"].as<bool>();
  if (has("threshold")) o.front_end.threshold = static_cast<float>(vm["threshold"].as<double>());
  if (has("points")) {
    const std::string points = vm["points"].as<std::string>();
    if (points != "cartesian" && points != "polar")
      throw std::invalid_argument("--points must be cartesian or polar, not '" + points + "'");
    o.front_end.cartesian = points == "cartesian";
  }
  if (has("pixel")) o.front_end.cartesian_resolution = vm["pixel"].as<double>();
  if (has("max-range")) o.front_end.max_range = vm["max-range"].as<double>();
  const bool boreas = vm["format"].as<std::string>() == "boreas";
  if (has("bin-size"))
    (boreas ? o.sequence.boreas.range_resolution : o.sequence.oxford.convention.range_resolution) =
        vm["bin-size"].as<double>();
  if (has("bins")) (boreas ? o.sequence.boreas.expected_bins : o.sequence.oxford.expected_bins) = vm["bins"].as<int>();
  if (has("start")) o.start = vm["start"].as<std::size_t>();
  if (has("max-cycles")) o.max_scans = vm["max-cycles"].as<std::size_t>();
  if (has("threads")) o.threads = vm["threads"].as<int>();
  if (vm["no-prefetch"].as<bool>()) o.threads = 1;
  o.validate();
  return o;
}

NuScenesDataset openDataset(const po::variables_map& vm) {
  if (!vm.count("dataroot")) throw std::invalid_argument("--format nuscenes needs --dataroot DIR");
  return NuScenesDataset(vm["dataroot"].as<std::string>(), vm["version"].as<std::string>());
}

std::vector<const NuScenesScene*> selectScenes(const NuScenesDataset& dataset, const po::variables_map& vm) {
  std::vector<const NuScenesScene*> scenes;
  if (vm["scene"].as<std::string>() == "all")
    for (const auto& s : dataset.scenes()) scenes.push_back(&s);
  else
    scenes.push_back(&dataset.scene(vm["scene"].as<std::string>()));
  return scenes;
}

std::vector<std::string> sequenceDirs(const po::variables_map& vm) {
  if (!vm.count("sequence") || vm["sequence"].as<std::vector<std::string>>().empty())
    throw std::invalid_argument("--format " + vm["format"].as<std::string>() + " needs --sequence DIR");
  return vm["sequence"].as<std::vector<std::string>>();
}

void Progress::operator()(std::size_t done, std::size_t total) const {
  if (!enabled || (done % 10 != 0 && done != total)) return;
  const int width = 30;
  const int filled = total ? static_cast<int>(width * done / total) : width;
  std::fprintf(stderr, "\r%-12s [%s%s] %zu/%zu", label.c_str(),
               std::string(static_cast<std::size_t>(filled), '#').c_str(),
               std::string(static_cast<std::size_t>(width - filled), ' ').c_str(), done, total);
  if (done == total) std::fprintf(stderr, "\n");
}

}  // namespace apps
}  // namespace radar_ndt
