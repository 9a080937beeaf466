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
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/sim/radar_sim.h"

using namespace radar_ndt;
namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

struct Setting {
  std::string group;
  std::function<void(double)> set;
  std::function<double()> get;
  std::string help;
};

template <typename T>
Setting setting(const char* group, T& field, const char* help) {
  return {group, [&field](double v) { field = static_cast<T>(v); }, [&field] { return static_cast<double>(field); }, help};
}

/// Every simulator setting by name (`--set name=value`), with its documentation.
std::map<std::string, Setting> settings(sim::WorldOptions& w, sim::ScanningOptions& s, sim::AutomotiveOptions& a) {
  std::map<std::string, Setting> m;
  m["road_half_width_min"] = setting("world", w.road_half_width_min, "m, kerb to the path's centre line (min)");
  m["road_half_width_max"] = setting("world", w.road_half_width_max, "m, kerb to the path's centre line (max)");
  m["building_probability"] = setting("world", w.building_probability, "per side and 30 m block: a facade, else open land");
  m["facade_gap_probability"] = setting("world", w.facade_gap_probability, "per 3–9 m facade piece: a gap");
  m["open_land_objects"] = setting("world", w.open_land_objects, "per side and open 30 m block: mean scattered buildings, bushes, cars");
  m["parked_car_probability"] = setting("world", w.parked_car_probability, "per 6 m kerb slot");
  m["pole_spacing"] = setting("world", w.pole_spacing, "m, mean spacing of lamp posts and signs");
  m["tree_probability"] = setting("world", w.tree_probability, "per 12 m slot: a street tree (trunk and crown)");
  m["fence_probability"] = setting("world", w.fence_probability, "per open block: a metal fence");
  m["hedge_probability"] = setting("world", w.hedge_probability, "per open block without a fence: a hedge");
  m["movers_per_km"] = setting("world", w.movers_per_km, "moving cars and buses per km of path");
  m["bus_share"] = setting("world", w.bus_share, "share of movers that are buses");
  m["mirror"] = setting("world", w.mirror, "1: the seed's world mirrored across the path (same draws; exact on a straight path)");
  m["azimuths"] = setting("scanning", s.azimuths, "azimuths a sweep");
  m["bins"] = setting("scanning", s.bins, "range bins an azimuth");
  m["range_resolution"] = setting("scanning", s.range_resolution, "m per bin");
  m["sweep_period"] = setting("scanning", s.sweep_period, "s a sweep; azimuth a is taken at stamp + a·period/azimuths");
  m["beam_width_deg"] = setting("scanning", s.beam_width_deg, "deg, −3 dB beam width (smearing across azimuths)");
  m["beam_rays"] = setting("scanning", s.beam_rays, "sub-rays cast across ±0.9 beam widths");
  m["range_psf_sigma"] = setting("scanning", s.range_psf_sigma, "m, σ of the range response's main lobe");
  m["range_sidelobe_db"] = setting("scanning", s.range_sidelobe_db, "dB, range sidelobes relative to the peak");
  m["range_sidelobe_length"] = setting("scanning", s.range_sidelobe_length, "m, exponential decay of the sidelobes");
  m["range_loss_db_per_decade"] = setting("scanning", s.range_loss_db_per_decade, "dB power fall per decade of range beyond 10 m");
  m["target_snr_db"] = setting("scanning", s.target_snr_db, "dB over the noise mean of a facade at 10 m, normal incidence");
  m["noise_rise_db"] = setting("scanning", s.noise_rise_db, "dB the noise mean grows from 0 m to max_range");
  m["display_db_range"] = setting("scanning", s.display_db_range, "dB spanned by pixel values 0..255");
  m["noise_display_level"] = setting("scanning", s.noise_display_level, "0..1 pixel value of the noise mean at 0 m");
  m["display_knee_db"] = setting("scanning", s.display_knee_db, "dB over the noise mean above which display_compression applies");
  m["display_compression"] = setting("scanning", s.display_compression, "slope of the display above the knee (1: none; 0.35 matches RADIATE's thresholded powers)");
  m["speckle_looks"] = setting("scanning", s.speckle_looks, "gamma shape of target fluctuation (1: Rayleigh)");
  m["ghost_probability"] = setting("scanning", s.ghost_probability, "share of facades and vehicle sides that mirror (multipath ghosts)");
  m["ghost_attenuation_db"] = setting("scanning", s.ghost_attenuation_db, "dB a ghost is below the direct return of what it shows");
  m["saturation_probability"] = setting("scanning", s.saturation_probability, "per azimuth: a saturated bright line");
  m["saturation_db"] = setting("scanning", s.saturation_db, "dB over the noise of a saturated line");
  m["leakage_db"] = setting("scanning", s.leakage_db, "dB over the noise of the near-range leakage (first ~1.5 m)");
  m["ground_clutter_db"] = setting("scanning", s.ground_clutter_db, "dB over the noise at 10 m of a cluttered 1 m ground cell (Rayleigh)");
  m["ground_clutter_cover"] = setting("scanning", s.ground_clutter_cover, "share of 1 m ground cells with clutter (grass, kerbs, gravel)");
  m["max_range"] = setting("scanning", s.max_range, "m rendered (beyond: noise only)");
  m["period"] = setting("automotive", a.period, "s between sweeps of one radar (13 Hz)");
  m["jitter"] = setting("automotive", a.jitter, "s, uniform timing jitter of each sweep");
  m["near_fov_deg"] = setting("automotive", a.near_fov_deg, "deg, ± azimuth of the near scan");
  m["near_range"] = setting("automotive", a.near_range, "m, reach of the near scan");
  m["far_fov_deg"] = setting("automotive", a.far_fov_deg, "deg, ± azimuth of the far scan");
  m["far_range"] = setting("automotive", a.far_range, "m, reach of the far scan");
  m["ray_step_deg"] = setting("automotive", a.ray_step_deg, "deg between cast rays");
  m["detection_probability"] = setting("automotive", a.detection_probability, "per surface return, scaled by the material's RCS");
  m["cluster_distance"] = setting("automotive", a.cluster_distance, "m: returns closer than this merge into one detection");
  m["max_detections"] = setting("automotive", a.max_detections, "detections a sweep (strongest kept)");
  m["clutter_per_sweep"] = setting("automotive", a.clutter_per_sweep, "mean false detections a sweep (random Doppler)");
  m["range_sigma"] = setting("automotive", a.range_sigma, "m, range noise (doubled in the far scan)");
  m["azimuth_sigma_deg"] = setting("automotive", a.azimuth_sigma_deg, "deg, azimuth noise at boresight (×2 at ±60°)");
  m["rcs_sigma_db"] = setting("automotive", a.rcs_sigma_db, "dB, RCS noise");
  m["doppler_sigma"] = setting("automotive", a.doppler_sigma, "m/s, Doppler noise");
  m["automotive_ghost_probability"] = setting("automotive", a.ghost_probability, "per detection on a vehicle: a multipath ghost");
  return m;
}

std::vector<std::string> radiateScans(const std::string& dir) {
  fs::path root(dir);
  if (fs::is_directory(root / "Navtech_Polar")) root /= "Navtech_Polar";
  if (!fs::is_directory(root)) throw std::invalid_argument("--realism: '" + dir + "' is not a directory");
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(root))
    if (e.path().extension() == ".png") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw std::invalid_argument("--realism: no .png scans in '" + root.string() + "'");
  return files;
}

std::vector<std::uint8_t> toPixels(const CartesianImage& image) {
  std::vector<std::uint8_t> px(image.power.size());
  for (std::size_t i = 0; i < px.size(); ++i)
    px[i] = image.power[i] < 0 ? 0 : static_cast<std::uint8_t>(std::min(255.f, image.power[i] * 255.f + 0.5f));
  return px;
}

}  // namespace

int main(int argc, char** argv) {
  std::string type = "scanning", trajectory_path, out, realism_dir, realism_png;
  std::size_t frames = 0, start = 0;
  std::uint64_t seed = 1;
  double period = 0.25, view_range = 62.5;
  int compression = 1;
  std::vector<std::string> sets;
  bool list = false, quiet = false;
  po::options_description opts("Options");
  // clang-format off
  opts.add_options()
    ("help,h", "print this help and exit")
    ("type", po::value(&type)->default_value("scanning"), "scanning (Oxford Radar RobotCar layout) | automotive (nuScenes layout)")
    ("trajectory", po::value(&trajectory_path), "ego trajectory, KITTI or TUM (e.g. ../shared/data/oxford-radar-gt/*.txt); default: a built-in 2-minute city drive")
    ("period", po::value(&period)->default_value(0.25), "s between poses of a trajectory without timestamps (KITTI)")
    ("out", po::value(&out), "output directory (created)")
    ("frames", po::value(&frames)->default_value(0), "scans (scanning) or front-radar sweeps (automotive) to write; 0: the whole trajectory")
    ("start", po::value(&start)->default_value(0), "first trajectory pose used")
    ("seed", po::value(&seed)->default_value(1), "world and noise seed: the same seed gives the same files")
    ("compression", po::value(&compression)->default_value(1), "zlib level of the scan PNGs (1 fast … 9 small)")
    ("set", po::value(&sets)->composing(), "override a simulator setting: --set name=value (repeatable; see --list-settings)")
    ("list-settings", po::bool_switch(&list), "print every simulator setting with its value and meaning, then exit")
    ("realism", po::value(&realism_dir), "compare: RADIATE Navtech_Polar scans in this directory vs --frames (default 10) simulated scans, "
                                         "Cartesian 0.125 m/px within 62.5 m; prints the statistics side by side")
    ("realism-png", po::value(&realism_png), "with --realism: write a simulated scan (left) and the first real one (right) as one PNG")
    ("realism-view", po::value(&view_range)->default_value(62.5), "with --realism-png: show ±this many metres around the sensor")
    ("quiet,q", po::bool_switch(&quiet), "no progress line");
  // clang-format on
  const std::string usage =
      "Usage: radar_sim --type scanning|automotive [--trajectory GT.txt] --out DIR [--frames N] [--seed S] [--start K]\n"
      "       radar_sim --realism RADIATE_DIR [--realism-png side_by_side.png] [--frames N]\n"
      "Scanning: DIR/radar/<stamp>.png, DIR/radar.timestamps, DIR/gt/radar_odometry.csv (Oxford conventions)\n"
      "and DIR/gt/poses.txt (KITTI, first pose identity). Automotive: a nuScenes dataroot, tables in\n"
      "DIR/v1.0-sim, five ARS408 radars at nuScenes' mountings. Settings: --list-settings, docs/simulator.md.";
  po::variables_map vm;
  const int rc = apps::parseCommandLine(argc, argv, opts, usage, vm);
  if (rc >= 0) return rc;

  return apps::runGuarded("radar_sim", [&]() {
    sim::WorldOptions world;
    sim::ScanningOptions scanning;
    sim::AutomotiveOptions automotive;
    auto table = settings(world, scanning, automotive);
    for (const std::string& s : sets) {
      const auto eq = s.find('=');
      if (eq == std::string::npos) throw std::invalid_argument("--set '" + s + "': expected name=value");
      const auto it = table.find(s.substr(0, eq));
      if (it == table.end()) throw std::invalid_argument("--set: unknown setting '" + s.substr(0, eq) + "' (see --list-settings)");
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
      for (const char* group : {"world", "scanning", "automotive"}) {
        std::printf("%s:\n", group);
        for (const auto& [name, s] : table)
          if (s.group == group) std::printf("  %-28s %-10g %s\n", name.c_str(), s.get(), s.help.c_str());
      }
      return 0;
    }
    world.seed = seed;
    if (type != "scanning" && type != "automotive") throw std::invalid_argument("--type must be scanning or automotive, not '" + type + "'");

    const bool builtin = trajectory_path.empty();
    const sim::SimTrajectory ego =
        builtin ? sim::builtinDrive(120.0) : sim::SimTrajectory(readTrajectory(trajectory_path), period);
    const std::string source = builtin ? "the built-in drive" : trajectory_path;

    if (!realism_dir.empty()) {
      const std::size_t n = frames == 0 ? 10 : frames;
      PowerThreshold front;  // paper defaults: 0.125 m/px, 62.5 m, threshold 0.333
      const float thr = front.options().threshold;
      const sim::World w = sim::World::generate(ego, world);
      std::vector<PowerStatistics> simulated, real;
      PolarScan scan;
      CartesianImage first_sim;  // the one shown in --realism-png
      const std::size_t stride = std::max<std::size_t>(1, (ego.size() - std::min(start, ego.size() - 1)) / n);
      for (std::size_t k = 0; k < n && start + k * stride < ego.size(); ++k) {
        sim::renderScan(w, ego, ego.stamps()[start + k * stride], seed, k, scanning, scan);
        const CartesianImage img = front.cartesianImage(scan);
        simulated.push_back(powerStatistics(img, thr));
        if (k == n / 2) first_sim = img;  // mid-sequence: under way
      }
      const auto files = radiateScans(realism_dir);
      CartesianImage first_real;
      PowerThresholdOptions polar_options;
      polar_options.cartesian = false;
      const PowerThreshold polar(polar_options);
      std::vector<double> ms_cartesian, ms_polar, n_polar;
      for (const auto& f : files) {
        const PolarScan real_scan = readRadiatePolarPng(f);
        const CartesianImage img = front.cartesianImage(real_scan);
        real.push_back(powerStatistics(img, thr));
        if (real.size() == 1) first_real = img;
        // The two front-end paths on the same real scan (points and time).
        pcl::PointCloud<PointRadar> cloud;
        auto t0 = std::chrono::steady_clock::now();
        front.compute(real_scan, cloud);
        auto t1 = std::chrono::steady_clock::now();
        polar.compute(real_scan, cloud);
        auto t2 = std::chrono::steady_clock::now();
        ms_cartesian.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        ms_polar.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
        n_polar.push_back(static_cast<double>(cloud.size()));
      }
      auto median = [](std::vector<double> v) {
        std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
        return v[v.size() / 2];
      };
      const PowerStatistics s = medianStatistics(simulated), r = medianStatistics(real);
      std::printf("Realism: median over %zu simulated scans (%s, seed %llu) and %zu real RADIATE scans (%s)\n"
                  "Cartesian %.3f m/px within %.1f m (from %.1f m), threshold %.3f\n\n",
                  simulated.size(), source.c_str(), static_cast<unsigned long long>(seed), real.size(), realism_dir.c_str(),
                  front.options().cartesian_resolution, front.options().max_range, front.options().min_range, thr);
      std::printf("%-24s %10s %10s %8s  %s\n", "statistic", "simulated", "RADIATE", "ratio", "within ±30 %");
      auto row = [](const char* name, double a, double b, bool check) {
        const double ratio = b != 0 ? a / b : 0.0;
        std::printf("%-24s %10.4f %10.4f %8.2f  %s\n", name, a, b, ratio, check ? (std::abs(ratio - 1) <= 0.3 ? "yes" : "NO") : "-");
      };
      row("fraction above thres", s.fraction_above, r.fraction_above, true);
      row("power p50", s.p50, r.p50, true);
      row("power p90", s.p90, r.p90, true);
      row("power p99", s.p99, r.p99, true);
      // What the power shift weighs (w = p − s, s = thres): the spread of the thresholded powers.
      row("above: p-thres p50", s.excess_p50, r.excess_p50, true);
      row("above: p-thres p90", s.excess_p90, r.excess_p90, true);
      row("above: p-thres p99", s.excess_p99, r.excess_p99, true);
      row("points per scan", static_cast<double>(s.points), static_cast<double>(r.points), false);
      std::printf("\nFront-end on the real scans (median): Cartesian %zu points in %.1f ms, polar %.0f points in %.2f ms\n",
                  r.points, median(ms_cartesian), median(n_polar), median(ms_polar));
      if (!realism_png.empty()) {
        const int full = first_sim.size;
        if (first_real.size != full) throw std::logic_error("Cartesian images of different sizes");
        const int size = std::clamp(2 * static_cast<int>(std::lround(view_range / first_sim.resolution)), 2, full);
        const int off = (full - size) / 2;
        const auto a = toPixels(first_sim), b = toPixels(first_real);
        const int gap = 8, width = 2 * size + gap;
        std::vector<std::uint8_t> px(static_cast<std::size_t>(width) * size, 255);
        for (int y = 0; y < size; ++y) {
          const std::size_t src = static_cast<std::size_t>(y + off) * full + off;
          std::copy_n(&a[src], size, &px[static_cast<std::size_t>(y) * width]);
          std::copy_n(&b[src], size, &px[static_cast<std::size_t>(y) * width + size + gap]);
        }
        writePng(realism_png, width, size, 1, px.data(), 9);
        std::printf("\nwrote %s: simulated (left), %s (right), front up\n", realism_png.c_str(), files.front().c_str());
      }
      return 0;
    }

    if (out.empty()) throw std::invalid_argument("--out is required (or --realism / --list-settings)");
    sim::SequenceOptions seq;
    seq.start = start;
    seq.frames = frames;
    seq.png_compression = compression;
    seq.progress = !quiet;
    const sim::SequenceSummary summary = type == "scanning"
                                             ? sim::writeScanningSequence(out, ego, world, scanning, seq)
                                             : sim::writeAutomotiveSequence(out, ego, world, automotive, seq);
    std::printf("radar_sim: %s, %zu %s over %.1f s and %.2f km along %s, seed %llu -> %s (%.1f s, %.1f frames/s)\n",
                type.c_str(), summary.frames, type == "scanning" ? "scans" : "front-radar sweeps", summary.duration,
                summary.distance / 1000.0, source.c_str(), static_cast<unsigned long long>(seed), out.c_str(), summary.seconds,
                summary.frames / std::max(summary.seconds, 1e-9));
    return 0;
  });
}
