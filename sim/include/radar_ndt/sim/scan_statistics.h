#pragma once
// What a scanning radar's polar scans look like, in numbers: per range band, the share of raw
// polar bins above given power levels and percentiles of their power (power = byte / 255, every
// azimuth), plus the thresholded points the front-end makes of the scan. Used to compare the
// simulator with real scans of the same layout (radar_sim --realism) and to characterise a radar's
// data. Statistics are taken per scan, then the median over scans (and the scan-to-scan min and
// max beside it).

#include <cstddef>
#include <string>
#include <vector>

#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/io/polar_scan.h"

namespace radar_ndt {
namespace sim {

struct RangeBand {
  double lo = 0, hi = 0;  ///< metres: a bin belongs to [lo, hi) by its centre range
};

struct ScanStatisticsOptions {
  /// The scanning issue's bands: 2–15, 15–30, 30–45 and 45–62.5 m.
  std::vector<RangeBand> bands{{2.0, 15.0}, {15.0, 30.0}, {30.0, 45.0}, {45.0, 62.5}};
  std::vector<double> levels{0.2, 0.333, 0.5};        ///< fraction of bins with power above each
  std::vector<double> percentiles{50.0, 90.0, 99.0};  ///< of the power, nearest rank
  /// Throws std::invalid_argument naming the setting (empty or inverted band, level outside
  /// [0, 1], percentile outside (0, 100]).
  void validate() const;
};

struct BandStatistics {
  RangeBand band;
  std::size_t bins = 0;            ///< polar bins in the band (all azimuths)
  std::vector<double> above;       ///< per level: share of bins with power > level
  std::vector<double> percentile;  ///< per percentile: power (0..1, a multiple of 1/255)
};

struct ScanStatistics {
  std::vector<BandStatistics> bands;
  std::size_t points = 0;  ///< thresholded points of the scan (with a front-end; else 0)
};

/// Per band statistics of one scan's raw bins.
ScanStatistics scanStatistics(const PolarScan& scan, const ScanStatisticsOptions& options = {});
/// The same, with `points` the thresholded points `front_end` makes of the scan.
ScanStatistics scanStatistics(const PolarScan& scan, const PowerThreshold& front_end,
                              const ScanStatisticsOptions& options = {});

/// Field-wise summary over scans: the median, and the smallest and largest value of each field.
struct StatisticsSummary {
  ScanStatistics median, min, max;
  std::size_t scans = 0;
};
/// Throws std::invalid_argument when `scans` is empty or their bands differ.
StatisticsSummary summarize(const std::vector<ScanStatistics>& scans);

/// Whether simulated statistics reproduce real ones, field by field, with the scanning issue's
/// tolerances: fractions within ±25 % or ±0.002 (whichever is larger), percentiles within ±3/255
/// (8-bit power is coarse), points per scan within ±25 %.
struct RealismTolerance {
  double fraction_relative = 0.25, fraction_absolute = 0.002;
  double percentile_absolute = 3.0 / 255.0;
  double points_relative = 0.25;
};
struct RealismCheck {
  /// One line per band and field: "15-30 m, above 0.333: 0.0150 vs 0.0141".
  std::vector<std::string> failures;
  std::size_t fields = 0;  ///< fields compared
  /// Per field, whether it is within its tolerance, in order: each band's levels, then its
  /// percentiles; the points per scan last.
  std::vector<bool> within;
  /// Σ over the fields of min(|simulated − real| / tolerance, 5)²: 1 per field at the edge of its
  /// tolerance, 0 for a perfect match (how far off, where `failures` only says whether).
  double error = 0;
  bool passed() const { return failures.empty(); }
};
RealismCheck compareRealism(const ScanStatistics& simulated, const ScanStatistics& real,
                            const ScanStatisticsOptions& options, const RealismTolerance& tolerance = {});

}  // namespace sim
}  // namespace radar_ndt
