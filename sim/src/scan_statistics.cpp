#include "radar_ndt/sim/scan_statistics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace radar_ndt {
namespace sim {

void ScanStatisticsOptions::validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("ScanStatisticsOptions: " + what); };
  if (bands.empty()) fail("no range bands");
  for (const RangeBand& b : bands)
    if (!(b.lo >= 0) || !(b.hi > b.lo) || !std::isfinite(b.hi)) fail("a band must have 0 <= lo < hi, finite");
  for (double l : levels)
    if (!(l >= 0 && l <= 1)) fail("levels must lie in [0, 1]");
  for (double p : percentiles)
    if (!(p > 0 && p <= 100)) fail("percentiles must lie in (0, 100]");
}

ScanStatistics scanStatistics(const PolarScan& scan, const ScanStatisticsOptions& options) {
  options.validate();
  if (scan.azimuths <= 0 || scan.bins <= 0 || scan.power.size() != static_cast<std::size_t>(scan.azimuths) * scan.bins)
    throw std::invalid_argument("scanStatistics: the scan has no power image of its size");
  // One 256-bin histogram per band over every azimuth: the bins of a band are a contiguous run of
  // range bins, so each azimuth contributes a slice of its row.
  ScanStatistics out;
  for (const RangeBand& band : options.bands) {
    int b0 = scan.bins, b1 = -1;
    for (int b = 0; b < scan.bins; ++b) {
      const double r = scan.rangeOf(b);
      if (r >= band.lo && r < band.hi) {
        b0 = std::min(b0, b);
        b1 = std::max(b1, b);
      }
    }
    std::array<std::size_t, 256> hist{};
    for (int a = 0; a < scan.azimuths && b1 >= b0; ++a) {
      const std::uint8_t* row = scan.row(a);
      for (int b = b0; b <= b1; ++b) ++hist[row[b]];
    }
    BandStatistics s;
    s.band = band;
    for (std::size_t v : hist) s.bins += v;
    for (double level : options.levels) {
      std::size_t n = 0;
      for (int v = 0; v < 256; ++v)
        if (v / 255.0 > level) n += hist[v];
      s.above.push_back(s.bins ? static_cast<double>(n) / static_cast<double>(s.bins) : 0.0);
    }
    for (double p : options.percentiles) {
      // Nearest rank: the smallest value with at least p % of the bins at or below it.
      const std::size_t rank =
          std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(s.bins))));
      std::size_t cum = 0;
      int v = 0;
      for (; v < 255; ++v) {
        cum += hist[v];
        if (cum >= rank) break;
      }
      s.percentile.push_back(s.bins ? v / 255.0 : 0.0);
    }
    out.bands.push_back(s);
  }
  return out;
}

ScanStatistics scanStatistics(const PolarScan& scan, const PowerThreshold& front_end,
                              const ScanStatisticsOptions& options) {
  ScanStatistics st = scanStatistics(scan, options);
  pcl::PointCloud<PointRadar> cloud;
  front_end.compute(scan, cloud);
  st.points = cloud.size();
  return st;
}

StatisticsSummary summarize(const std::vector<ScanStatistics>& scans) {
  if (scans.empty()) throw std::invalid_argument("summarize: no scans");
  const ScanStatistics& first = scans.front();
  for (const ScanStatistics& s : scans) {
    if (s.bands.size() != first.bands.size()) throw std::invalid_argument("summarize: scans with different bands");
    for (std::size_t i = 0; i < s.bands.size(); ++i)
      if (s.bands[i].above.size() != first.bands[i].above.size() ||
          s.bands[i].percentile.size() != first.bands[i].percentile.size())
        throw std::invalid_argument("summarize: scans with different levels or percentiles");
  }
  StatisticsSummary out;
  out.scans = scans.size();
  out.median = out.min = out.max = first;
  std::vector<double> v(scans.size());
  // Applies median, min and max to one field, read by `get` and written by `set`.
  auto field = [&](auto get, auto set) {
    for (std::size_t k = 0; k < scans.size(); ++k) v[k] = get(scans[k]);
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    set(out.median, n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
    set(out.min, v.front());
    set(out.max, v.back());
  };
  field([](const ScanStatistics& s) { return static_cast<double>(s.points); },
        [](ScanStatistics& s, double x) { s.points = static_cast<std::size_t>(std::lround(x)); });
  for (std::size_t i = 0; i < first.bands.size(); ++i) {
    field([i](const ScanStatistics& s) { return static_cast<double>(s.bands[i].bins); },
          [i](ScanStatistics& s, double x) { s.bands[i].bins = static_cast<std::size_t>(std::lround(x)); });
    for (std::size_t j = 0; j < first.bands[i].above.size(); ++j)
      field([i, j](const ScanStatistics& s) { return s.bands[i].above[j]; },
            [i, j](ScanStatistics& s, double x) { s.bands[i].above[j] = x; });
    for (std::size_t j = 0; j < first.bands[i].percentile.size(); ++j)
      field([i, j](const ScanStatistics& s) { return s.bands[i].percentile[j]; },
            [i, j](ScanStatistics& s, double x) { s.bands[i].percentile[j] = x; });
  }
  return out;
}

RealismCheck compareRealism(const ScanStatistics& sim, const ScanStatistics& real, const ScanStatisticsOptions& options,
                            const RealismTolerance& tol) {
  if (sim.bands.size() != real.bands.size() || sim.bands.size() != options.bands.size())
    throw std::invalid_argument("compareRealism: the two statistics have different bands");
  RealismCheck check;
  char line[160];
  for (std::size_t i = 0; i < real.bands.size(); ++i) {
    const BandStatistics &s = sim.bands[i], &r = real.bands[i];
    if (s.above.size() != options.levels.size() || r.above.size() != options.levels.size() ||
        s.percentile.size() != options.percentiles.size() || r.percentile.size() != options.percentiles.size())
      throw std::invalid_argument("compareRealism: statistics taken with other levels or percentiles");
    for (std::size_t j = 0; j < options.levels.size(); ++j) {
      ++check.fields;
      const double allowed = std::max(tol.fraction_relative * r.above[j], tol.fraction_absolute);
      check.error += std::pow(std::min(std::abs(s.above[j] - r.above[j]) / allowed, 5.0), 2);
      check.within.push_back(std::abs(s.above[j] - r.above[j]) <= allowed + 1e-12);
      if (!check.within.back()) {
        std::snprintf(line, sizeof line, "%g-%g m, above %g: %.4f vs %.4f", r.band.lo, r.band.hi, options.levels[j],
                      s.above[j], r.above[j]);
        check.failures.push_back(line);
      }
    }
    for (std::size_t j = 0; j < options.percentiles.size(); ++j) {
      ++check.fields;
      check.error += std::pow(std::min(std::abs(s.percentile[j] - r.percentile[j]) / tol.percentile_absolute, 5.0), 2);
      check.within.push_back(std::abs(s.percentile[j] - r.percentile[j]) <= tol.percentile_absolute + 1e-9);
      if (!check.within.back()) {
        std::snprintf(line, sizeof line, "%g-%g m, p%g: %.0f/255 vs %.0f/255", r.band.lo, r.band.hi,
                      options.percentiles[j], 255 * s.percentile[j], 255 * r.percentile[j]);
        check.failures.push_back(line);
      }
    }
  }
  ++check.fields;
  const double rp = static_cast<double>(real.points), sp = static_cast<double>(sim.points);
  check.error += std::pow(std::min(std::abs(sp - rp) / std::max(tol.points_relative * rp, 1.0), 5.0), 2);
  check.within.push_back(std::abs(sp - rp) <= tol.points_relative * rp);
  if (!check.within.back()) {
    std::snprintf(line, sizeof line, "points per scan: %.0f vs %.0f", sp, rp);
    check.failures.push_back(line);
  }
  return check;
}

}  // namespace sim
}  // namespace radar_ndt
