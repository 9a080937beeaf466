// radar_sim: simulate a scanning-radar (Oxford Radar RobotCar or Boreas layout), automotive-radar
// (nuScenes layout) or 4D radar (a ROS bag in its driver's layout, sim/sim_4d.h) sequence along a
// trajectory, or compare simulated scans with real ones (sim/realism.h). Its settings are the
// simulator's field tables (sim/sim_settings.h).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app_common.h"
#include "radar_ndt/io/boreas_scan.h"
#include "radar_ndt/io/nuscenes_can_bus.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/sim/radar_sim.h"
#include "sim/realism.h"
#include "sim/sim_4d.h"
#include "sim/sim_settings.h"

using namespace radar_ndt;
namespace po = boost::program_options;

namespace {

/// 2000-01-01 in s since 1970: trajectory times from then on are dates, earlier ones times from a start.
constexpr double kYear2000 = 946684800.0;

struct Args {
  std::string type = "scanning", layout = "oxford", trajectory, out, realism, realism_png, profile, imu = "none";
  std::string preset = "ti_iwr6843_rio", sensors;
  double rate = 0;
  std::int64_t start_stamp = 0;
  bool chirp_flags = false, list = false, markdown = false, quiet = false;
  std::size_t frames = 0, start = 0;
  std::uint64_t seed = 1;
  double period = 0.25, view_range = 62.5, realism_threshold = 0.333, chirp_beta = 0.049;
  int compression = 1;
  std::vector<std::string> sets;
};

/// --type 4d's own options.
void add4DOptions(po::options_description& o, Args& a) {
  // clang-format off
  o.add_options()
    ("preset", po::value(&a.preset)->default_value("ti_iwr6843_rio"),
     "--type 4d: the radar: ti_iwr6843_rio (hand-held; the bag as ti_mmwave_rospkg writes it, read by "
     "preset:ti_iwr6843_rio) | ars548 (a car; Snail-Radar's /ars548, preset:snail_radar_ars548) | oculii_eagle (a "
     "car; NTU4DRadLM's /radar_enhanced_pcl, preset:ntu4dradlm_eagle)")
    ("sensors", po::value(&a.sensors),
     "--type 4d: the sensor description whose topics, Doppler sign, radar mounting and IMU axes the bag follows "
     "(a file or preset:NAME); default: the preset's")
    ("rate", po::value(&a.rate)->default_value(0), "--type 4d: scans a second; 0: the radar's (ars548 20 Hz, others 10 Hz)");
  // clang-format on
}

// Kept as one function: the option table, read in the order --help prints it.
po::options_description options(Args& a) {
  po::options_description o("Options");
  // clang-format off
  o.add_options()
    ("help,h", "print this help and exit")
    ("type", po::value(&a.type)->default_value("scanning"),
     "scanning (Oxford Radar RobotCar layout) | automotive (nuScenes layout) | 4d (a 4D radar and a 6-axis IMU "
     "along a 6-DoF motion: DIR/radar.bag in the radar's driver's layout, DIR/sensors.yaml that reads it, "
     "DIR/groundtruth.txt (TUM), DIR/radar/<µs>.pcd)")

    ("layout", po::value(&a.layout)->default_value("oxford"),
     "scanning: oxford (radar.timestamps, radar/, gt/radar_odometry.csv) | boreas (radar/<stamp>.png named by the "
     "sweep's middle row, applanix/radar_poses.csv; the bin by the scans' date as Boreas: 0.0596 m and 3360 bins "
     "before 2021-09-21, 0.04381 m and 6848 after)")
    ("trajectory", po::value(&a.trajectory),
     "ego trajectory, KITTI, TUM or a Boreas pose file (applanix/radar_poses.csv: its times and place are kept "
     "for --layout boreas) (e.g. ../shared/data/oxford-radar-gt/*.txt); default: a built-in 2-minute city drive. "
     "--type 4d: the body's 6-DoF motion, TUM (e.g. ../shared/data/handheld-6dof/*.txt) or a Boreas pose file "
     "(its 6-DoF poses); default: a built-in hand-held walk (ti_iwr6843_rio) or car drive with a ramp")
    ("start-stamp", po::value(&a.start_stamp),
     "the first scan's time (µs since 1970); default, --layout boreas: the trajectory's own time when it is a "
     "date (a Boreas pose file's; a TUM file timed from 0 is not), else 1547120000000000 (2019-01-10)")
    ("chirp-flags", po::bool_switch(&a.chirp_flags),
     "--layout boreas: write the flag byte as alternating up/down chirp types, as 2024 Boreas scans, and shift "
     "each azimuth's ranges by +-beta times the scenery's radial velocity as its chirp does")
    ("chirp-beta", po::value(&a.chirp_beta)->default_value(0.049),
     "with --chirp-flags: the range-Doppler coupling beta (s; m of shift per m/s); 0: flags without shifts")
    ("imu", po::value(&a.imu)->default_value("none"),
     "also write a gyro of this grade: none | mems (a consumer MEMS gyro) | navigation (navigation grade, as "
     "Boreas's Applanix); --layout boreas: applanix/imu.csv; --type automotive: the CAN bus as nuScenes' "
     "(can_bus/<scene>_ms_imu.json, 100 Hz, and the wheel speeds, <scene>_zoe_veh_info.json); its errors are the "
     "imu_* and wheel_* settings (--list-settings); --type 4d: a 6-axis IMU (gyro and accelerometer with "
     "gravity, 200 Hz) on the description's IMU topic in its axes, mems the rio rig's ADIS16448")
    ("period", po::value(&a.period)->default_value(0.25), "s between poses of a trajectory without timestamps (KITTI)")
    ("out", po::value(&a.out), "output directory (created)")
    ("frames", po::value(&a.frames)->default_value(0),
     "scans (scanning) or front-radar sweeps (automotive) to write; 0: the whole trajectory")
    ("start", po::value(&a.start)->default_value(0), "first trajectory pose used")
    ("seed", po::value(&a.seed)->default_value(1), "world and noise seed: the same seed gives the same files")
    ("profile", po::value(&a.profile),
     "scanning sensor profile: oxford (the CTS350-X as the Oxford dataset recorded it; default) | "
     "radiate (the earlier calibration to RADIATE's scans); --realism: the real layout's by default")
    ("compression", po::value(&a.compression)->default_value(1), "zlib level of the scan PNGs (1 fast … 9 small)")
    ("set", po::value(&a.sets)->composing(),
     "override a simulator setting: --set name=value (repeatable; see --list-settings)")
    ("list-settings", po::bool_switch(&a.list), "print every simulator setting with its value and meaning, then exit")
    ("markdown", po::bool_switch(&a.markdown),
     "with --list-settings: one markdown table, each setting's value in both profiles (oxford, radiate) and "
     "its meaning (docs/simulator.md holds it)")
    ("realism", po::value(&a.realism),
     "compare: the real scans of this Oxford, Boreas or RADIATE sequence against --frames (default 10) "
     "simulated ones in the same layout (spread over the trajectory from --start); per range band "
     "the share of polar bins above 0.2, 0.333, 0.5 and power percentiles, and the front-end's points")
    ("realism-png", po::value(&a.realism_png),
     "with --realism: write the first real scan (left) and a simulated one (right), Cartesian, as one PNG")
    ("realism-threshold", po::value(&a.realism_threshold)->default_value(0.333),
     "with --realism: the front-end threshold of the comparison (the paper's by default)")
    ("realism-view", po::value(&a.view_range)->default_value(62.5),
     "with --realism-png: show ±this many metres around the sensor")
    ("quiet,q", po::bool_switch(&a.quiet), "no progress line");
  // clang-format on
  add4DOptions(o, a);
  return o;
}

/// The trajectory, near the origin (a Boreas pose file is in UTM metres; `origin` is where it was
/// and the Boreas layout puts the place back in its pose file).
sim::SimTrajectory loadTrajectory(const Args& a, bool boreas, Trajectory& path, Eigen::Vector3d& origin) {
  path = a.trajectory.empty() ? Trajectory{} : readTrajectory(a.trajectory);
  origin = Eigen::Vector3d::Zero();
  if (!path.empty() && (boreas || path.poses.front().translation().norm() > 1e4)) {
    origin = path.poses.front().translation();
    for (auto& p : path.poses) p.translation() -= origin;
  }
  return a.trajectory.empty() ? sim::builtinDrive(120.0) : sim::SimTrajectory(path, a.period);
}

/// Whether --imu asks for a gyro (and, automotive, wheel speeds) beside the sequence.
bool wantsImu(const Args& a) {
  return parseEnum<sim::ImuGrade>(a.imu) != sim::ImuGrade::None;
}

/// Writes the sequence --type and --layout ask for and prints what was written.
void writeSequence(const po::variables_map& vm, const Args& a, apps::SimConfig config, const sim::SimTrajectory& ego,
                   const Trajectory& path, const Eigen::Vector3d& origin) {
  if (a.out.empty()) throw std::invalid_argument("--out is required (or --realism / --list-settings)");
  const bool boreas = a.layout == "boreas";
  sim::SequenceOptions seq;
  seq.start = a.start;
  seq.frames = a.frames;
  seq.png_compression = a.compression;
  seq.progress = !a.quiet;
  if (vm.count("start-stamp"))
    seq.start_stamp_us = a.start_stamp;
  else if (boreas && path.hasStamps() && a.start < path.size() && path.stamps[a.start] >= kYear2000)
    seq.start_stamp_us = std::llround(path.stamps[a.start] * 1e6);  // a date (a Boreas pose file's)
  sim::SequenceSummary summary;
  if (boreas) {
    // The Boreas sensor of the scans' date, as the reader will decide it.
    sim::ScanningOptions& s = config.scanning;
    s.range_resolution = boreasRangeResolution(1e-6 * static_cast<double>(seq.start_stamp_us));
    s.bins = s.range_resolution == kBoreasBinBeforeUpgrade ? 3360 : 6848;
    s.range_offset_bins = 0.5;
    sim::BoreasLayoutOptions layout;
    layout.enu_east = origin.x();
    layout.enu_north = origin.y();
    layout.chirp_flags = a.chirp_flags;
    layout.chirp_beta = a.chirp_beta;
    layout.imu = wantsImu(a);
    layout.imu_options = config.imu;
    summary = sim::writeBoreasSequence(a.out, ego, config.world, s, seq, layout);
  } else {
    summary = a.type == "scanning" ? sim::writeScanningSequence(a.out, ego, config.world, config.scanning, seq)
                                   : sim::writeAutomotiveSequence(a.out, ego, config.world, config.automotive, seq);
    if (a.type == "automotive" && wantsImu(a)) {
      // The car's CAN bus, from a second before the first sweep to a second after the last.
      const double t0 = ego.stamps()[seq.start];
      std::vector<CanImuMessage> imu;
      std::vector<CanWheelMessage> wheels;
      sim::simulateCanBus(ego, std::max(ego.startTime(), t0 - 1.0),
                          std::min(ego.endTime(), t0 + summary.duration + 1.0), t0, seq.start_stamp_us, config.imu,
                          config.wheels, config.world.seed, imu, wheels);
      writeNuScenesCanBus(a.out, seq.scene_name, imu, wheels);
    }
  }
  std::printf("radar_sim: %s, %zu %s over %.1f s and %.2f km along %s, seed %llu -> %s (%.1f s, %.1f frames/s)\n",
              a.type.c_str(), summary.frames, a.type == "scanning" ? "scans" : "front-radar sweeps", summary.duration,
              summary.distance / 1000.0, a.trajectory.empty() ? "the built-in drive" : a.trajectory.c_str(),
              static_cast<unsigned long long>(config.world.seed), a.out.c_str(), summary.seconds,
              summary.frames / std::max(summary.seconds, 1e-9));
}

void checkArgs(const Args& a) {
  if (a.type != "scanning" && a.type != "automotive" && a.type != "4d")
    throw std::invalid_argument("--type must be scanning, automotive or 4d, not '" + a.type + "'");
  if (a.layout != "oxford" && a.layout != "boreas")
    throw std::invalid_argument("--layout must be oxford or boreas, not '" + a.layout + "'");
  if (a.layout == "boreas" && a.type != "scanning")
    throw std::invalid_argument("--layout boreas is for --type scanning");
  if (a.chirp_flags && a.layout != "boreas") throw std::invalid_argument("--chirp-flags is for --layout boreas");
  if (wantsImu(a) && a.type == "scanning" && a.layout != "boreas")
    throw std::invalid_argument(
        "--imu is for --layout boreas (the only scanning layout with an IMU file) or --type automotive");
}

int run4D(const Args& a) {
  if (!a.realism.empty() || a.list || a.layout != "oxford" || !a.sets.empty())
    throw std::invalid_argument(
        "--type 4d takes --preset, --sensors, --trajectory, --imu, --rate, --frames, --seed "
        "and --out");
  apps::Sim4DRequest r;
  r.preset = a.preset;
  r.sensors = a.sensors;
  r.trajectory = a.trajectory;
  r.imu = a.imu;
  r.out = a.out;
  r.rate = a.rate;
  r.frames = a.frames;
  r.seed = a.seed;
  apps::writeSequence4D(r);
  return 0;
}

int run(const po::variables_map& vm, const Args& a) {
  if (a.type == "4d") return run4D(a);
  // --realism: the real scans first, so the profile can default to their layout's.
  apps::RealismRequest realism;
  if (!a.realism.empty()) realism.real = apps::readRealScans(a.realism, realism.layout);
  const sim::ScanningProfile profile = !a.profile.empty()            ? parseEnum<sim::ScanningProfile>(a.profile)
                                       : realism.layout == "RADIATE" ? sim::ScanningProfile::Radiate
                                                                     : sim::ScanningProfile::Oxford;
  // The profile (sensor and world) for scanning output and --realism; the automotive output keeps
  // WorldOptions' default world. --seed first: --set may override any setting.
  apps::SimConfig config;
  config.world.seed = a.seed;
  if (a.type == "scanning" || !a.realism.empty()) sim::applyProfile(profile, config.world, config.scanning);
  config.imu = sim::imuPreset(parseEnum<sim::ImuGrade>(a.imu));
  if (a.type == "automotive") config.imu.rate = 100.0;  // nuScenes' ms_imu
  for (const std::string& s : a.sets) apps::applySetting(s, config);
  if (a.list) {
    if (a.markdown) {
      std::vector<std::pair<std::string, apps::SimConfig>> columns;
      for (const auto p : {sim::ScanningProfile::Oxford, sim::ScanningProfile::Radiate}) {
        apps::SimConfig c = config;
        sim::applyProfile(p, c.world, c.scanning);
        for (const std::string& s : a.sets) apps::applySetting(s, c);
        columns.emplace_back(toString(p), c);
      }
      std::printf("%s", apps::settingsMarkdown(columns).c_str());
    } else {
      std::printf("profile %s\n%s", toString(profile), apps::listSettings(config).c_str());
    }
    return 0;
  }
  checkArgs(a);
  Trajectory path;
  Eigen::Vector3d origin;
  const sim::SimTrajectory ego = loadTrajectory(a, a.layout == "boreas", path, origin);
  if (a.realism.empty()) {
    writeSequence(vm, a, config, ego, path, origin);
    return 0;
  }
  realism.dir = a.realism;
  realism.frames = a.frames == 0 ? 10 : a.frames;
  realism.start = a.start;
  realism.seed = config.world.seed;
  realism.threshold = a.realism_threshold;
  realism.png = a.realism_png;
  realism.view_range = a.view_range;
  realism.profile = profile;
  realism.source = a.trajectory.empty() ? "the built-in drive" : a.trajectory;
  apps::runRealism(realism, ego, config.world, config.scanning);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  const po::options_description opts = options(a);
  const char* usage =
      "Usage: radar_sim --type scanning|automotive [--layout oxford|boreas] [--trajectory GT.txt] --out DIR [--frames "
      "N] "
      "[--seed S] [--start K]\n"
      "       radar_sim --type 4d --preset ti_iwr6843_rio|ars548|oculii_eagle [--trajectory TUM_OR_BOREAS_POSES] "
      "[--imu none|mems|navigation] --out DIR\n"
      "       radar_sim --realism OXFORD_BOREAS_OR_RADIATE_DIR [--profile P] [--trajectory GT.txt] [--frames N] "
      "[--realism-png out.png]\n"
      "Scanning: DIR/radar/<stamp>.png, DIR/radar.timestamps, DIR/gt/radar_odometry.csv (Oxford conventions)\n"
      "and DIR/gt/poses.txt (KITTI, first pose identity); --layout boreas: DIR/radar/<stamp>.png,\n"
      "DIR/applanix/radar_poses.csv (Boreas conventions), with --imu DIR/applanix/imu.csv, and DIR/gt/poses.txt. "
      "Automotive: a nuScenes dataroot, tables "
      "in\n"
      "DIR/v1.0-sim, five ARS408 radars at nuScenes' mountings; with --imu DIR/can_bus/. Settings: --list-settings, "
      "docs/simulator.md.";
  po::variables_map vm;
  const int rc = apps::parseCommandLine(argc, argv, opts, usage, vm);
  if (rc >= 0) return rc;
  return apps::runGuarded("radar_sim", [&]() { return run(vm, a); });
}
