#pragma once
// Scanning-radar front-end (paper, Sec. III-A): a polar power scan → PointCloud<PointRadar> by
// keeping what returns more power than a fixed threshold. Two paths, chosen by a setting:
//  - Cartesian (the paper's): the scan is resampled bilinearly onto a square grid (default
//    0.125 m/pixel) within the range limit, and each pixel above the threshold is a point at the
//    pixel centre;
//  - polar: each (azimuth, bin) cell above the threshold is a point at its range and angle.
// Every point keeps its power (for the weights of eq. 1–2), a covariance from the range
// resolution and the beam width (plus the pixel size on the Cartesian path), and its time offset
// from the scan's reference timestamp (its azimuth's timestamp), for motion compensation.

#include <cstdint>
#include <memory>
#include <vector>

#include <pcl/point_cloud.h>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/point_types.h"

namespace radar_ndt {

struct PowerThresholdOptions {
  bool cartesian = true;                ///< false: the direct polar path
  double cartesian_resolution = 0.125;  ///< m per pixel (paper)
  double max_range = 62.5;              ///< m (paper: farther returns blur in the Cartesian image)
  /// m; returns nearer than this are dropped: the radar's own mount and the vehicle roof light
  /// up the first bins of every azimuth and would pin the match to zero motion.
  double min_range = 2.0;
  float threshold = 0.333f;     ///< power in 0..1 (paper)
  double beam_width_deg = 2.0;  ///< −3 dB azimuth beam width (CTS350-X: 2°); σθ = width / 2.355
  /// Throws std::invalid_argument naming the setting out of range.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void PowerThresholdOptions::fields(Visit&& visit) {
  using S = PowerThresholdOptions;
  visit(&S::cartesian, Field("cartesian", "the paper's Cartesian image (else one point per polar cell)")
                           .spelled("points", "polar", "cartesian"));
  visit(&S::cartesian_resolution,
        Field("cartesian_resolution", "cartesian: metres per pixel").unit("m").positive().cli("pixel"));
  visit(&S::max_range, Field("max_range", "the front-end's range limit").unit("m").positive().cli("max-range"));
  visit(&S::min_range, Field("min_range", "returns nearer than this dropped (the radar's mount)").unit("m").atLeast(0));
  visit(&S::threshold,
        Field("threshold", "power threshold of the front-end (power is 0..1)").atLeast(0).below(1).cli("threshold"));
  visit(&S::beam_width_deg, Field("beam_width_deg", "-3 dB azimuth beam width").unit("deg").positive());
}

/// A Cartesian power image centred on the sensor: row 0 is the far front (+x), column 0 the far
/// left (+y). Pixels outside [min_range, max_range] hold −1.
struct CartesianImage {
  int size = 0;              ///< pixels per side
  double resolution = 0.0;   ///< m per pixel
  std::vector<float> power;  ///< size × size, 0..1, or −1 outside the ring
  /// Centre of pixel (row, col) in the vehicle frame.
  double x(int row) const { return (0.5 * size - row - 0.5) * resolution; }
  double y(int col) const { return (0.5 * size - col - 0.5) * resolution; }
};

/// Caches the per-pixel geometry of the last scan layout it saw (shared by its copies). Thread-safe:
/// threads may call compute on one instance at once (the pipelines' workers do), and share the cache.
class PowerThreshold {
 public:
  explicit PowerThreshold(const PowerThresholdOptions& options = {});
  const PowerThresholdOptions& options() const { return options_; }

  /// Thresholded points of `scan` in the vehicle frame (z = 0), per the chosen path.
  void compute(const PolarScan& scan, pcl::PointCloud<PointRadar>& out) const;

  /// The scan resampled onto the Cartesian grid (bilinear in azimuth and range). Also what the
  /// realism statistics are computed on.
  CartesianImage cartesianImage(const PolarScan& scan) const;

 private:
  struct Geometry;  // per-pixel range bin and angle, cached for the last scan geometry
  struct GeometryCache;
  std::shared_ptr<const Geometry> geometry(const PolarScan& scan) const;
  std::shared_ptr<const Geometry> buildGeometry(const PolarScan& scan) const;

  PowerThresholdOptions options_;
  std::shared_ptr<GeometryCache> cache_;
};

/// Statistics of a Cartesian image, for comparing simulated scans with real ones.
struct PowerStatistics {
  std::size_t pixels = 0;                  ///< pixels within the ring
  double fraction_above = 0.0;             ///< share of them above the threshold
  double p50 = 0.0, p90 = 0.0, p99 = 0.0;  ///< power percentiles (0..1)
  std::size_t points = 0;                  ///< thresholded points (the front-end's output size)
  /// Percentiles of p − threshold over the pixels above the threshold: the power-shift weights
  /// w = p − s of the paper's eq. (1) at s = threshold, what the matcher's weighting acts on.
  double excess_p50 = 0.0, excess_p90 = 0.0, excess_p99 = 0.0;
};
PowerStatistics powerStatistics(const CartesianImage& image, float threshold);
/// Field-wise median over scans (empty input: all zero).
PowerStatistics medianStatistics(std::vector<PowerStatistics> scans);

}  // namespace radar_ndt
