// radar_sim: simulate a scanning-radar (Oxford Radar RobotCar layout) or automotive-radar
// (nuScenes layout) sequence along a trajectory, or compare simulated scans with real ones.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>

#include "app_common.h"
#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/io/boreas_scan.h"
#include "radar_ndt/io/png_image.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/radiate_scan.h"
#include "radar_ndt/io/scanning_sequence.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/sim/radar_sim.h"
#include "radar_ndt/sim/scan_statistics.h"

using namespace radar_ndt;
using radar_ndt::sim::compareRealism;
using radar_ndt::sim::RealismCheck;
using radar_ndt::sim::ScanStatistics;
using radar_ndt::sim::scanStatistics;
using radar_ndt::sim::ScanStatisticsOptions;
using radar_ndt::sim::StatisticsSummary;
using radar_ndt::sim::summarize;
namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

/// 2000-01-01 in s since 1970: trajectory times from then on are dates, earlier ones times from a start.
constexpr double kYear2000 = 946684800.0;

struct Setting {
  std::string group;
  std::function<void(double)> set;
  std::function<double()> get;
  std::string help;
};

template <typename T>
Setting setting(const char* group, T& field, const char* help) {
  return {group, [&field](double v) { field = static_cast<T>(v); }, [&field] { return static_cast<double>(field); },
          help};
}

/// Every simulator setting by name (`--set name=value`), with its documentation.
std::map<std::string, Setting> settings(sim::WorldOptions& w, sim::ScanningOptions& s, sim::AutomotiveOptions& a) {
  std::map<std::string, Setting> m;
  m["road_half_width_min"] = setting("world", w.road_half_width_min, "m, kerb to the path's centre line (min)");
  m["road_half_width_max"] = setting("world", w.road_half_width_max, "m, kerb to the path's centre line (max)");
  m["building_probability"] =
      setting("world", w.building_probability, "per side and 30 m block: a facade, else open land");
  m["facade_gap_probability"] = setting("world", w.facade_gap_probability, "per 3–9 m facade piece: a gap");
  m["open_land_objects"] =
      setting("world", w.open_land_objects, "per side and open 30 m block: mean scattered buildings, bushes, cars");
  m["parked_car_probability"] = setting("world", w.parked_car_probability, "per 6 m kerb slot");
  m["pole_spacing"] = setting("world", w.pole_spacing, "m, mean spacing of lamp posts and signs");
  m["tree_probability"] = setting("world", w.tree_probability, "per 12 m slot: a street tree (trunk and crown)");
  m["fence_probability"] = setting("world", w.fence_probability, "per open block: a metal fence");
  m["hedge_probability"] = setting("world", w.hedge_probability, "per open block without a fence: a hedge");
  m["movers_per_km"] = setting("world", w.movers_per_km, "moving cars and buses per km of path");
  m["bus_share"] = setting("world", w.bus_share, "share of movers that are buses");
  m["mirror"] =
      setting("world", w.mirror, "1: the seed's world mirrored across the path (same draws; exact on a straight path)");
  m["back_rows"] =
      setting("world", w.back_rows, "per side: rows of building walls behind the street's facades (0: none)");
  m["back_row_spacing"] = setting("world", w.back_row_spacing, "m between those rows (±30 %)");
  m["back_row_gap_probability"] = setting("world", w.back_row_gap_probability, "per 5–20 m piece of a back row: a gap");
  m["azimuths"] = setting("scanning", s.azimuths, "azimuths a sweep");
  m["bins"] = setting("scanning", s.bins, "range bins an azimuth");
  m["range_resolution"] = setting("scanning", s.range_resolution, "m per bin");
  m["sweep_period"] = setting("scanning", s.sweep_period, "s a sweep; azimuth a is taken at stamp + a·period/azimuths");
  m["beam_width_deg"] = setting("scanning", s.beam_width_deg, "deg, −3 dB beam width (smearing across azimuths)");
  m["beam_rays"] = setting("scanning", s.beam_rays, "sub-rays cast across ±0.9 beam widths");
  m["range_psf_sigma"] = setting("scanning", s.range_psf_sigma, "m, σ of the range response's main lobe");
  m["range_sidelobe_db"] =
      setting("scanning", s.range_sidelobe_db, "dB, range sidelobes relative to each bin of a return");
  m["range_sidelobe_length"] = setting("scanning", s.range_sidelobe_length, "m, exponential decay of the sidelobes");
  m["range_loss_db_per_decade"] =
      setting("scanning", s.range_loss_db_per_decade, "dB power fall per decade of range beyond 10 m");
  m["target_snr_db"] =
      setting("scanning", s.target_snr_db, "dB over the noise mean of a facade at 10 m, normal incidence");
  m["noise_rise_db"] = setting("scanning", s.noise_rise_db, "dB the noise mean grows from 0 m to max_range");
  m["display_db_range"] = setting("scanning", s.display_db_range, "dB spanned by pixel values 0..255");
  m["noise_display_level"] = setting("scanning", s.noise_display_level, "0..1 pixel value of the noise mean at 0 m");
  m["display_knee_db"] =
      setting("scanning", s.display_knee_db, "dB over the noise mean above which display_compression applies");
  m["display_compression"] =
      setting("scanning", s.display_compression,
              "slope of the display above the knee (1: none; 0.35 matches RADIATE's thresholded powers)");
  m["speckle_looks"] = setting("scanning", s.speckle_looks, "gamma shape of target fluctuation (1: Rayleigh)");
  m["ghost_probability"] =
      setting("scanning", s.ghost_probability, "share of facades and vehicle sides that mirror (multipath ghosts)");
  m["ghost_attenuation_db"] =
      setting("scanning", s.ghost_attenuation_db, "dB a ghost is below the direct return of what it shows");
  m["saturation_probability"] = setting("scanning", s.saturation_probability, "per azimuth: a saturated bright line");
  m["saturation_db"] = setting("scanning", s.saturation_db, "dB over the noise of a saturated line");
  m["leakage_db"] = setting("scanning", s.leakage_db, "dB over the noise of the near-range leakage (first ~1.5 m)");
  m["ground_clutter_db"] =
      setting("scanning", s.ground_clutter_db, "dB over the noise at 10 m of a cluttered 1 m ground cell (Rayleigh)");
  m["ground_clutter_cover"] =
      setting("scanning", s.ground_clutter_cover, "share of 1 m ground cells with clutter (grass, kerbs, gravel)");
  m["max_range"] = setting("scanning", s.max_range, "m rendered (beyond: noise only)");
  m["range_offset_bins"] = setting("scanning", s.range_offset_bins, "bin b lies at (b + offset) · range_resolution");
  m["display_counts"] =
      setting("scanning", s.display_counts,
              "1: Navtech's counts, n = ⌊P⌋ stored as ⌊20·log10 n + 0.12⌋ (0.5 dB a value); 0: the display above");
  m["noise_counts"] = setting("scanning", s.noise_counts, "mean noise power in counts (display_counts)");
  m["leakage_length"] = setting("scanning", s.leakage_length, "m, exponential decay of the near-range leakage");
  m["azimuth_sidelobe_db"] = setting("scanning", s.azimuth_sidelobe_db,
                                     "dB, antenna sidelobes in azimuth relative to the main lobe (−200: none)");
  m["azimuth_sidelobe_width_deg"] =
      setting("scanning", s.azimuth_sidelobe_width_deg, "deg, exponential fall of the azimuth sidelobes");
  m["range_pedestal_db"] = setting("scanning", s.range_pedestal_db,
                                   "dB below a return of its long range tail, the radial streaks (−200: none)");
  m["scatterer_density"] = setting("scanning", s.scatterer_density, "point scatterers off the road a m² (0: none)");
  m["scatterer_db"] =
      setting("scanning", s.scatterer_db, "dB, mean scatterer strength relative to a facade at the same range");
  m["scatterer_sigma_db"] =
      setting("scanning", s.scatterer_sigma_db, "dB, log-normal spread of the scatterer strengths");
  m["scatterer_clearance"] = setting("scanning", s.scatterer_clearance, "m, no scatterer closer than this to the path");
  m["depth_scale"] = setting("scanning", s.depth_scale, "scales every material's return depth");
  m["range_pedestal_length"] =
      setting("scanning", s.range_pedestal_length, "m, exponential decay of the range pedestal");
  m["over_occluder_db"] =
      setting("scanning", s.over_occluder_db,
              "dB: what lies behind the first opaque surface returns this much weaker (−200: hidden)");
  m["period"] = setting("automotive", a.period, "s between sweeps of one radar (13 Hz)");
  m["jitter"] = setting("automotive", a.jitter, "s, uniform timing jitter of each sweep");
  m["near_fov_deg"] = setting("automotive", a.near_fov_deg, "deg, ± azimuth of the near scan");
  m["near_range"] = setting("automotive", a.near_range, "m, reach of the near scan");
  m["far_fov_deg"] = setting("automotive", a.far_fov_deg, "deg, ± azimuth of the far scan");
  m["far_range"] = setting("automotive", a.far_range, "m, reach of the far scan");
  m["ray_step_deg"] = setting("automotive", a.ray_step_deg, "deg between cast rays");
  m["detection_probability"] =
      setting("automotive", a.detection_probability, "per surface return, scaled by the material's RCS");
  m["cluster_distance"] =
      setting("automotive", a.cluster_distance, "m: returns closer than this merge into one detection");
  m["max_detections"] = setting("automotive", a.max_detections, "detections a sweep (strongest kept)");
  m["clutter_per_sweep"] = setting("automotive", a.clutter_per_sweep, "mean false detections a sweep (random Doppler)");
  m["range_sigma"] = setting("automotive", a.range_sigma, "m, range noise (doubled in the far scan)");
  m["azimuth_sigma_deg"] = setting("automotive", a.azimuth_sigma_deg, "deg, azimuth noise at boresight (×2 at ±60°)");
  m["rcs_sigma_db"] = setting("automotive", a.rcs_sigma_db, "dB, RCS noise");
  m["doppler_sigma"] = setting("automotive", a.doppler_sigma, "m/s, Doppler noise");
  m["automotive_ghost_probability"] =
      setting("automotive", a.ghost_probability, "per detection on a vehicle: a multipath ghost");
  return m;
}

/// The real scans of an Oxford (radar.timestamps, radar/<stamp>.png), Boreas (radar/<stamp>.png, no
/// index) or RADIATE (Navtech_Polar/) sequence directory, and the layout's name.
std::vector<PolarScan> readRealScans(const std::string& dir, std::string& layout) {
  const fs::path root(dir);
  std::vector<PolarScan> scans;
  if (fs::exists(root / "radar.timestamps")) {
    layout = "Oxford";
    const ScanningSequence sequence(dir, ScanFormat::Oxford);  // the reader the odometry uses
    for (std::size_t k = 0; k < sequence.size(); ++k) scans.push_back(sequence.load(k));
  } else if (fs::is_directory(root / "radar")) {
    layout = "Boreas";
    const ScanningSequence sequence(dir, ScanFormat::Boreas);
    for (std::size_t k = 0; k < sequence.size(); ++k) scans.push_back(sequence.load(k));
  } else {
    layout = "RADIATE";
    fs::path polar = fs::is_directory(root / "Navtech_Polar") ? root / "Navtech_Polar" : root;
    if (!fs::is_directory(polar)) throw std::invalid_argument("--realism: '" + dir + "' is not a directory");
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(polar))
      if (e.path().extension() == ".png") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) scans.push_back(readRadiatePolarPng(f));
  }
  if (scans.empty())
    throw std::invalid_argument("--realism: no scans in '" + dir +
                                "' (an Oxford sequence with radar.timestamps, a Boreas one with radar/, or RADIATE's "
                                "Navtech_Polar/)");
  return scans;
}

std::vector<std::uint8_t> toPixels(const CartesianImage& image) {
  std::vector<std::uint8_t> px(image.power.size());
  for (std::size_t i = 0; i < px.size(); ++i)
    px[i] = image.power[i] < 0 ? 0 : static_cast<std::uint8_t>(std::min(255.f, image.power[i] * 255.f + 0.5f));
  return px;
}

}  // namespace

int main(int argc, char** argv) {
  std::string type = "scanning", layout_name = "oxford", trajectory_path, out, realism_dir, realism_png, profile_name;
  std::int64_t start_stamp = 0;
  bool chirp_flags = false;
  std::size_t frames = 0, start = 0;
  std::uint64_t seed = 1;
  double period = 0.25, view_range = 62.5, realism_threshold = 0.333, chirp_beta = 0.049;
  int compression = 1;
  std::vector<std::string> sets;
  bool list = false, quiet = false;
  po::options_description opts("Options");
  // clang-format off
  opts.add_options()
    ("help,h", "print this help and exit")
    ("type", po::value(&type)->default_value("scanning"),
     "scanning (Oxford Radar RobotCar layout) | automotive (nuScenes layout)")
    ("layout", po::value(&layout_name)->default_value("oxford"),
     "scanning: oxford (radar.timestamps, radar/, gt/radar_odometry.csv) | boreas (radar/<stamp>.png named by the "
     "sweep's middle row, applanix/radar_poses.csv; the bin by the scans' date as Boreas: 0.0596 m and 3360 bins "
     "before 2021-09-21, 0.04381 m and 6848 after)")
    ("trajectory", po::value(&trajectory_path),
     "ego trajectory, KITTI, TUM or a Boreas pose file (applanix/radar_poses.csv: its times and place are kept "
     "for --layout boreas) (e.g. ../shared/data/oxford-radar-gt/*.txt); default: a built-in 2-minute city drive")
    ("start-stamp", po::value(&start_stamp),
     "the first scan's time (µs since 1970); default, --layout boreas: the trajectory's own time when it is a "
     "date (a Boreas pose file's; a TUM file timed from 0 is not), else 1547120000000000 (2019-01-10)")
    ("chirp-flags", po::bool_switch(&chirp_flags),
     "--layout boreas: write the flag byte as alternating up/down chirp types, as 2024 Boreas scans, and shift "
     "each azimuth's ranges by +-beta times the scenery's radial velocity as its chirp does")
    ("chirp-beta", po::value(&chirp_beta)->default_value(0.049),
     "with --chirp-flags: the range-Doppler coupling beta (s; m of shift per m/s); 0: flags without shifts")
    ("period", po::value(&period)->default_value(0.25), "s between poses of a trajectory without timestamps (KITTI)")
    ("out", po::value(&out), "output directory (created)")
    ("frames", po::value(&frames)->default_value(0),
     "scans (scanning) or front-radar sweeps (automotive) to write; 0: the whole trajectory")
    ("start", po::value(&start)->default_value(0), "first trajectory pose used")
    ("seed", po::value(&seed)->default_value(1), "world and noise seed: the same seed gives the same files")
    ("profile", po::value(&profile_name),
     "scanning sensor profile: oxford (the CTS350-X as the Oxford dataset recorded it; default) | "
     "radiate (the earlier calibration to RADIATE's scans); --realism: the real layout's by default")
    ("compression", po::value(&compression)->default_value(1), "zlib level of the scan PNGs (1 fast … 9 small)")
    ("set", po::value(&sets)->composing(),
     "override a simulator setting: --set name=value (repeatable; see --list-settings)")
    ("list-settings", po::bool_switch(&list), "print every simulator setting with its value and meaning, then exit")
    ("realism", po::value(&realism_dir),
     "compare: the real scans of this Oxford, Boreas or RADIATE sequence against --frames (default 10) "
     "simulated ones in the same layout (spread over the trajectory from --start); per range band "
     "the share of polar bins above 0.2, 0.333, 0.5 and power percentiles, and the front-end's points")
    ("realism-png", po::value(&realism_png),
     "with --realism: write the first real scan (left) and a simulated one (right), Cartesian, as one PNG")
    ("realism-threshold", po::value(&realism_threshold)->default_value(0.333),
     "with --realism: the front-end threshold of the comparison (the paper's by default)")
    ("realism-view", po::value(&view_range)->default_value(62.5),
     "with --realism-png: show ±this many metres around the sensor")
    ("quiet,q", po::bool_switch(&quiet), "no progress line");
  // clang-format on
  const std::string usage =
      "Usage: radar_sim --type scanning|automotive [--layout oxford|boreas] [--trajectory GT.txt] --out DIR [--frames "
      "N] "
      "[--seed S] [--start K]\n"
      "       radar_sim --realism OXFORD_BOREAS_OR_RADIATE_DIR [--profile P] [--trajectory GT.txt] [--frames N] "
      "[--realism-png out.png]\n"
      "Scanning: DIR/radar/<stamp>.png, DIR/radar.timestamps, DIR/gt/radar_odometry.csv (Oxford conventions)\n"
      "and DIR/gt/poses.txt (KITTI, first pose identity); --layout boreas: DIR/radar/<stamp>.png,\n"
      "DIR/applanix/radar_poses.csv (Boreas conventions) and DIR/gt/poses.txt. Automotive: a nuScenes dataroot, tables "
      "in\n"
      "DIR/v1.0-sim, five ARS408 radars at nuScenes' mountings. Settings: --list-settings, docs/simulator.md.";
  po::variables_map vm;
  const int rc = apps::parseCommandLine(argc, argv, opts, usage, vm);
  if (rc >= 0) return rc;

  return apps::runGuarded("radar_sim", [&]() {
    sim::WorldOptions world;
    sim::ScanningOptions scanning;
    sim::AutomotiveOptions automotive;
    // --realism: the real scans first, so the profile can default to their layout's.
    std::string layout;
    const std::vector<PolarScan> real_scans =
        realism_dir.empty() ? std::vector<PolarScan>{} : readRealScans(realism_dir, layout);
    const sim::ScanningProfile profile = !profile_name.empty() ? sim::parseScanningProfile(profile_name)
                                         : layout == "RADIATE" ? sim::ScanningProfile::Radiate
                                                               : sim::ScanningProfile::Oxford;
    // The profile (sensor and world) for scanning output and --realism; the automotive output keeps
    // WorldOptions' default world.
    if (type == "scanning" || !realism_dir.empty()) sim::applyProfile(profile, world, scanning);
    auto table = settings(world, scanning, automotive);
    for (const std::string& s : sets) {
      const auto eq = s.find('=');
      if (eq == std::string::npos) throw std::invalid_argument("--set '" + s + "': expected name=value");
      const auto it = table.find(s.substr(0, eq));
      if (it == table.end())
        throw std::invalid_argument("--set: unknown setting '" + s.substr(0, eq) + "' (see --list-settings)");
      std::size_t used = 0;
      double v = 0;
      try {
        v = std::stod(s.substr(eq + 1), &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != s.size() - eq - 1 || !std::isfinite(v))
        throw std::invalid_argument("--set '" + s + "': the value is not a number");
      it->second.set(v);
    }
    if (list) {
      std::printf("profile %s\n", sim::toString(profile));
      for (const char* group : {"world", "scanning", "automotive"}) {
        std::printf("%s:\n", group);
        for (const auto& [name, s] : table)
          if (s.group == group) std::printf("  %-30s %-10g %s\n", name.c_str(), s.get(), s.help.c_str());
      }
      return 0;
    }
    world.seed = seed;
    if (type != "scanning" && type != "automotive")
      throw std::invalid_argument("--type must be scanning or automotive, not '" + type + "'");

    if (layout_name != "oxford" && layout_name != "boreas")
      throw std::invalid_argument("--layout must be oxford or boreas, not '" + layout_name + "'");
    const bool boreas = layout_name == "boreas";
    if (boreas && type != "scanning") throw std::invalid_argument("--layout boreas is for --type scanning");
    if (chirp_flags && !boreas) throw std::invalid_argument("--chirp-flags is for --layout boreas");
    const bool builtin = trajectory_path.empty();
    Trajectory path = builtin ? Trajectory{} : readTrajectory(trajectory_path);
    // The simulator works near the origin (a Boreas pose file is in UTM metres); the Boreas layout
    // puts the place back in its pose file.
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    if (!path.empty() && (boreas || path.poses.front().translation().norm() > 1e4)) {
      origin = path.poses.front().translation();
      for (auto& p : path.poses) p.translation() -= origin;
    }
    const sim::SimTrajectory ego = builtin ? sim::builtinDrive(120.0) : sim::SimTrajectory(path, period);
    const std::string source = builtin ? "the built-in drive" : trajectory_path;

    if (!realism_dir.empty()) {
      const std::size_t n = frames == 0 ? 10 : frames;
      // Simulated scans in the real scans' layout, so both are compared bin for bin.
      const PolarScan& ref = real_scans.front();
      scanning.azimuths = ref.azimuths;
      scanning.bins = ref.bins;
      scanning.range_resolution = ref.range_resolution;
      scanning.range_offset_bins = ref.range_offset_bins;
      PowerThresholdOptions front_options;  // the paper's front-end: 0.125 m/px within 62.5 m
      front_options.threshold = static_cast<float>(realism_threshold);
      const PowerThreshold front(front_options);
      const ScanStatisticsOptions stat_options;
      auto measure = [&](const PolarScan& s) { return scanStatistics(s, front, stat_options); };
      std::vector<ScanStatistics> real, simulated;
      std::vector<PowerStatistics> real_image, simulated_image;  // the front-end's Cartesian image
      const float thr = front.options().threshold;
      // ms of the front-end per scan, once its geometry is cached (the first call of a run builds it).
      auto front_ms = [&front](const PolarScan& s) {
        pcl::PointCloud<PointRadar> cloud;
        front.compute(s, cloud);
        const auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < 3; ++i) front.compute(s, cloud);
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / 3;
      };
      std::vector<double> real_ms, simulated_ms;
      for (const PolarScan& s : real_scans) {
        real_ms.push_back(front_ms(s));
        real.push_back(measure(s));
        real_image.push_back(powerStatistics(front.cartesianImage(s), thr));
      }
      const sim::World w = sim::World::generate(ego, world);
      PolarScan scan, shown;
      const std::size_t first = std::min(start, ego.size() - 1);
      const std::size_t stride = std::max<std::size_t>(1, (ego.size() - first) / n);
      for (std::size_t k = 0; k < n && first + k * stride < ego.size(); ++k) {
        sim::renderScan(w, ego, ego.stamps()[first + k * stride], seed, k, scanning, scan);
        simulated_ms.push_back(front_ms(scan));
        simulated.push_back(measure(scan));
        simulated_image.push_back(powerStatistics(front.cartesianImage(scan), thr));
        if (k == n / 2) shown = scan;  // mid-sequence: under way
      }
      const StatisticsSummary r = summarize(real), m = summarize(simulated);
      const RealismCheck check = compareRealism(m.median, r.median, stat_options);
      std::printf(
          "Realism: %zu real %s scans (%s) against %zu simulated (profile %s, %s from pose %zu, seed %llu),\n"
          "both %d azimuths x %d bins of %.4f m; median over scans [scan-to-scan min..max]; power = byte/255\n\n",
          r.scans, layout.c_str(), realism_dir.c_str(), m.scans, sim::toString(profile), source.c_str(), first,
          static_cast<unsigned long long>(seed), ref.azimuths, ref.bins, ref.range_resolution);
      std::printf("| band | statistic | real | simulated | within |\n|---|---|---|---|---|\n");
      std::size_t field = 0;  // into check.within, in its order
      auto frac = [](double x) {
        char b[32];
        std::snprintf(b, sizeof b, "%.4f", x);
        return std::string(b);
      };
      auto pct = [](double x) {
        char b[32];
        std::snprintf(b, sizeof b, "%.3f (%d)", x, static_cast<int>(std::lround(255 * x)));
        return std::string(b);
      };
      for (std::size_t i = 0; i < stat_options.bands.size(); ++i) {
        const auto &rb = r.median.bands[i], &mb = m.median.bands[i];
        char band[32];
        std::snprintf(band, sizeof band, "%g-%g m", rb.band.lo, rb.band.hi);
        for (std::size_t j = 0; j < stat_options.levels.size(); ++j) {
          const bool ok = check.within[field++];
          std::printf("| %s | above %g | %s [%s..%s] | %s [%s..%s] | %s |\n", band, stat_options.levels[j],
                      frac(rb.above[j]).c_str(), frac(r.min.bands[i].above[j]).c_str(),
                      frac(r.max.bands[i].above[j]).c_str(), frac(mb.above[j]).c_str(),
                      frac(m.min.bands[i].above[j]).c_str(), frac(m.max.bands[i].above[j]).c_str(), ok ? "yes" : "NO");
        }
        for (std::size_t j = 0; j < stat_options.percentiles.size(); ++j) {
          const bool ok = check.within[field++];
          std::printf("| %s | p%g | %s [%s..%s] | %s [%s..%s] | %s |\n", band, stat_options.percentiles[j],
                      pct(rb.percentile[j]).c_str(), pct(r.min.bands[i].percentile[j]).c_str(),
                      pct(r.max.bands[i].percentile[j]).c_str(), pct(mb.percentile[j]).c_str(),
                      pct(m.min.bands[i].percentile[j]).c_str(), pct(m.max.bands[i].percentile[j]).c_str(),
                      ok ? "yes" : "NO");
        }
      }
      const bool points_ok = check.within[field];
      std::printf("| 2-62.5 m | thresholded points per scan | %zu [%zu..%zu] | %zu [%zu..%zu] | %s |\n",
                  r.median.points, r.min.points, r.max.points, m.median.points, m.min.points, m.max.points,
                  points_ok ? "yes" : "NO");
      std::printf(
          "\n%zu of %zu within the tolerances (fractions ±25 %% or ±0.002, percentiles ±3/255, points ±25 %%); "
          "error %.1f (the sum over the fields of (difference / tolerance)², each capped at 25)\n",
          check.fields - check.failures.size(), check.fields, check.error);
      // The front-end's view: its Cartesian image (0.125 m/px, 2–62.5 m) and what the power shift
      // weighs, p − thres over the pixels above the threshold (medians over scans).
      const PowerStatistics ri = medianStatistics(real_image), si = medianStatistics(simulated_image);
      std::printf(
          "\nThe front-end's Cartesian image (%.3f m/px, %.1f-%.1f m, threshold %.3f), medians over scans:\n\n"
          "| statistic | real | simulated | ratio |\n|---|---|---|---|\n",
          front.options().cartesian_resolution, front.options().min_range, front.options().max_range,
          front.options().threshold);
      auto irow = [](const char* name, double a, double b) {
        std::printf("| %s | %.4f | %.4f | %.2f |\n", name, a, b, a != 0 ? b / a : 0.0);
      };
      irow("pixels above the threshold", ri.fraction_above, si.fraction_above);
      irow("front-end ms per scan", apps::median(real_ms), apps::median(simulated_ms));
      irow("pixel power p50", ri.p50, si.p50);
      irow("pixel power p90", ri.p90, si.p90);
      irow("pixel power p99", ri.p99, si.p99);
      irow("above the threshold: p - thres, p50", ri.excess_p50, si.excess_p50);
      irow("above the threshold: p - thres, p90", ri.excess_p90, si.excess_p90);
      irow("above the threshold: p - thres, p99", ri.excess_p99, si.excess_p99);
      if (!realism_png.empty()) {
        const CartesianImage a = front.cartesianImage(real_scans.front()), b = front.cartesianImage(shown);
        const int full = a.size;
        if (b.size != full) throw std::logic_error("Cartesian images of different sizes");
        const int size = std::clamp(2 * static_cast<int>(std::lround(view_range / a.resolution)), 2, full);
        const int off = (full - size) / 2;
        const auto pa = toPixels(a), pb = toPixels(b);
        const int gap = 8, width = 2 * size + gap;
        std::vector<std::uint8_t> px(static_cast<std::size_t>(width) * size, 255);
        for (int y = 0; y < size; ++y) {
          const std::size_t src = static_cast<std::size_t>(y + off) * full + off;
          std::copy_n(&pa[src], size, &px[static_cast<std::size_t>(y) * width]);
          std::copy_n(&pb[src], size, &px[static_cast<std::size_t>(y) * width + size + gap]);
        }
        writePng(realism_png, width, size, 1, px.data(), 9);
        std::printf(
            "\nwrote %s: the first real %s scan (left), a simulated one (right), Cartesian %.3f m/px, front up\n",
            realism_png.c_str(), layout.c_str(), a.resolution);
      }
      return 0;
    }

    if (out.empty()) throw std::invalid_argument("--out is required (or --realism / --list-settings)");
    sim::SequenceOptions seq;
    seq.start = start;
    seq.frames = frames;
    seq.png_compression = compression;
    seq.progress = !quiet;
    if (vm.count("start-stamp"))
      seq.start_stamp_us = start_stamp;
    else if (boreas && path.hasStamps() && start < path.size() && path.stamps[start] >= kYear2000)
      seq.start_stamp_us = std::llround(path.stamps[start] * 1e6);  // a date (a Boreas pose file's)
    sim::SequenceSummary summary;
    if (boreas) {
      // The Boreas sensor of the scans' date, as the reader will decide it.
      scanning.range_resolution = boreasRangeResolution(1e-6 * static_cast<double>(seq.start_stamp_us));
      scanning.bins = scanning.range_resolution == kBoreasBinBeforeUpgrade ? 3360 : 6848;
      scanning.range_offset_bins = 0.5;
      const sim::BoreasLayoutOptions layout{origin.x(), origin.y(), chirp_flags, chirp_beta};
      summary = sim::writeBoreasSequence(out, ego, world, scanning, seq, layout);
    } else {
      summary = type == "scanning" ? sim::writeScanningSequence(out, ego, world, scanning, seq)
                                   : sim::writeAutomotiveSequence(out, ego, world, automotive, seq);
    }
    std::printf("radar_sim: %s, %zu %s over %.1f s and %.2f km along %s, seed %llu -> %s (%.1f s, %.1f frames/s)\n",
                type.c_str(), summary.frames, type == "scanning" ? "scans" : "front-radar sweeps", summary.duration,
                summary.distance / 1000.0, source.c_str(), static_cast<unsigned long long>(seed), out.c_str(),
                summary.seconds, summary.frames / std::max(summary.seconds, 1e-9));
    return 0;
  });
}
