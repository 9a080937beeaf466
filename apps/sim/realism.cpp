#include "realism.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "app_common.h"
#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/io/png_image.h"
#include "radar_ndt/io/radiate_scan.h"
#include "radar_ndt/io/scanning_sequence.h"
#include "radar_ndt/sim/scan_statistics.h"

namespace radar_ndt {
namespace apps {

namespace fs = std::filesystem;
using sim::ScanStatistics;
using sim::ScanStatisticsOptions;
using sim::StatisticsSummary;

namespace {

std::vector<std::uint8_t> toPixels(const CartesianImage& image) {
  std::vector<std::uint8_t> px(image.power.size());
  for (std::size_t i = 0; i < px.size(); ++i)
    px[i] = image.power[i] < 0 ? 0 : static_cast<std::uint8_t>(std::min(255.f, image.power[i] * 255.f + 0.5f));
  return px;
}

/// ms of the front-end per scan, once its geometry is cached (the first call of a run builds it).
double frontEndMs(const PowerThreshold& front, const PolarScan& s) {
  pcl::PointCloud<PointRadar> cloud;
  front.compute(s, cloud);
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < 3; ++i) front.compute(s, cloud);
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / 3;
}

/// One side of the comparison: per-scan statistics, the front-end's image statistics and times.
struct Measured {
  std::vector<ScanStatistics> scans;
  std::vector<PowerStatistics> image;
  std::vector<double> ms;
  void add(const PolarScan& s, const PowerThreshold& front, const ScanStatisticsOptions& options) {
    ms.push_back(frontEndMs(front, s));
    scans.push_back(sim::scanStatistics(s, front, options));
    image.push_back(powerStatistics(front.cartesianImage(s), front.options().threshold));
  }
};

std::string fraction(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4f", x);
  return b;
}

std::string percentile(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3f (%d)", x, static_cast<int>(std::lround(255 * x)));
  return b;
}

/// The per range band table: real against simulated, median [min..max] over scans.
void printBandTable(const StatisticsSummary& r, const StatisticsSummary& m, const sim::RealismCheck& check,
                    const ScanStatisticsOptions& options) {
  std::printf("| band | statistic | real | simulated | within |\n|---|---|---|---|---|\n");
  std::size_t field = 0;  // into check.within, in its order
  for (std::size_t i = 0; i < options.bands.size(); ++i) {
    const auto &rb = r.median.bands[i], &mb = m.median.bands[i];
    char band[32];
    std::snprintf(band, sizeof band, "%g-%g m", rb.band.lo, rb.band.hi);
    for (std::size_t j = 0; j < options.levels.size(); ++j) {
      const bool ok = check.within[field++];
      std::printf("| %s | above %g | %s [%s..%s] | %s [%s..%s] | %s |\n", band, options.levels[j],
                  fraction(rb.above[j]).c_str(), fraction(r.min.bands[i].above[j]).c_str(),
                  fraction(r.max.bands[i].above[j]).c_str(), fraction(mb.above[j]).c_str(),
                  fraction(m.min.bands[i].above[j]).c_str(), fraction(m.max.bands[i].above[j]).c_str(),
                  ok ? "yes" : "NO");
    }
    for (std::size_t j = 0; j < options.percentiles.size(); ++j) {
      const bool ok = check.within[field++];
      std::printf("| %s | p%g | %s [%s..%s] | %s [%s..%s] | %s |\n", band, options.percentiles[j],
                  percentile(rb.percentile[j]).c_str(), percentile(r.min.bands[i].percentile[j]).c_str(),
                  percentile(r.max.bands[i].percentile[j]).c_str(), percentile(mb.percentile[j]).c_str(),
                  percentile(m.min.bands[i].percentile[j]).c_str(), percentile(m.max.bands[i].percentile[j]).c_str(),
                  ok ? "yes" : "NO");
    }
  }
  std::printf("| 2-62.5 m | thresholded points per scan | %zu [%zu..%zu] | %zu [%zu..%zu] | %s |\n", r.median.points,
              r.min.points, r.max.points, m.median.points, m.min.points, m.max.points,
              check.within[field] ? "yes" : "NO");
  std::printf(
      "\n%zu of %zu within the tolerances (fractions ±25 %% or ±0.002, percentiles ±3/255, points ±25 %%); "
      "error %.1f (the sum over the fields of (difference / tolerance)², each capped at 25)\n",
      check.fields - check.failures.size(), check.fields, check.error);
}

/// The front-end's view: its Cartesian image (0.125 m/px, 2–62.5 m) and what the power shift
/// weighs, p − thres over the pixels above the threshold (medians over scans).
void printImageTable(const PowerThreshold& front, const Measured& real, const Measured& simulated) {
  const PowerStatistics ri = medianStatistics(real.image), si = medianStatistics(simulated.image);
  std::printf(
      "\nThe front-end's Cartesian image (%.3f m/px, %.1f-%.1f m, threshold %.3f), medians over scans:\n\n"
      "| statistic | real | simulated | ratio |\n|---|---|---|---|\n",
      front.options().cartesian_resolution, front.options().min_range, front.options().max_range,
      front.options().threshold);
  auto row = [](const char* name, double a, double b) {
    std::printf("| %s | %.4f | %.4f | %.2f |\n", name, a, b, a != 0 ? b / a : 0.0);
  };
  row("pixels above the threshold", ri.fraction_above, si.fraction_above);
  row("front-end ms per scan", median(real.ms), median(simulated.ms));
  row("pixel power p50", ri.p50, si.p50);
  row("pixel power p90", ri.p90, si.p90);
  row("pixel power p99", ri.p99, si.p99);
  row("above the threshold: p - thres, p50", ri.excess_p50, si.excess_p50);
  row("above the threshold: p - thres, p90", ri.excess_p90, si.excess_p90);
  row("above the threshold: p - thres, p99", ri.excess_p99, si.excess_p99);
}

/// The first real scan (left) and a simulated one (right), Cartesian, as one PNG.
void writeSideBySide(const RealismRequest& r, const PowerThreshold& front, const PolarScan& shown) {
  const CartesianImage a = front.cartesianImage(r.real.front()), b = front.cartesianImage(shown);
  const int full = a.size;
  if (b.size != full) throw std::logic_error("Cartesian images of different sizes");
  const int size = std::clamp(2 * static_cast<int>(std::lround(r.view_range / a.resolution)), 2, full);
  const int off = (full - size) / 2;
  const auto pa = toPixels(a), pb = toPixels(b);
  const int gap = 8, width = 2 * size + gap;
  std::vector<std::uint8_t> px(static_cast<std::size_t>(width) * size, 255);
  for (int y = 0; y < size; ++y) {
    const std::size_t src = static_cast<std::size_t>(y + off) * full + off;
    std::copy_n(&pa[src], size, &px[static_cast<std::size_t>(y) * width]);
    std::copy_n(&pb[src], size, &px[static_cast<std::size_t>(y) * width + size + gap]);
  }
  writePng(r.png, width, size, 1, px.data(), 9);
  std::printf("\nwrote %s: the first real %s scan (left), a simulated one (right), Cartesian %.3f m/px, front up\n",
              r.png.c_str(), r.layout.c_str(), a.resolution);
}

}  // namespace

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

void runRealism(const RealismRequest& r, const sim::SimTrajectory& ego, const sim::WorldOptions& world,
                sim::ScanningOptions scanning) {
  // Simulated scans in the real scans' layout, so both are compared bin for bin.
  const PolarScan& ref = r.real.front();
  scanning.azimuths = ref.azimuths;
  scanning.bins = ref.bins;
  scanning.range_resolution = ref.range_resolution;
  scanning.range_offset_bins = ref.range_offset_bins;
  PowerThresholdOptions front_options;  // the paper's front-end: 0.125 m/px within 62.5 m
  front_options.threshold = static_cast<float>(r.threshold);
  const PowerThreshold front(front_options);
  const ScanStatisticsOptions stat_options;
  Measured real, simulated;
  for (const PolarScan& s : r.real) real.add(s, front, stat_options);
  const sim::World w = sim::World::generate(ego, world);
  PolarScan scan, shown;
  const std::size_t first = std::min(r.start, ego.size() - 1);
  const std::size_t stride = std::max<std::size_t>(1, (ego.size() - first) / r.frames);
  for (std::size_t k = 0; k < r.frames && first + k * stride < ego.size(); ++k) {
    sim::renderScan(w, ego, ego.stamps()[first + k * stride], r.seed, k, scanning, scan);
    simulated.add(scan, front, stat_options);
    if (k == r.frames / 2) shown = scan;  // mid-sequence: under way
  }
  const StatisticsSummary rs = sim::summarize(real.scans), ms = sim::summarize(simulated.scans);
  const sim::RealismCheck check = sim::compareRealism(ms.median, rs.median, stat_options);
  std::printf(
      "Realism: %zu real %s scans (%s) against %zu simulated (profile %s, %s from pose %zu, seed %llu),\n"
      "both %d azimuths x %d bins of %.4f m; median over scans [scan-to-scan min..max]; power = byte/255\n\n",
      rs.scans, r.layout.c_str(), r.dir.c_str(), ms.scans, toString(r.profile), r.source.c_str(), first,
      static_cast<unsigned long long>(r.seed), ref.azimuths, ref.bins, ref.range_resolution);
  printBandTable(rs, ms, check, stat_options);
  printImageTable(front, real, simulated);
  if (!r.png.empty()) writeSideBySide(r, front, shown);
}

}  // namespace apps
}  // namespace radar_ndt
