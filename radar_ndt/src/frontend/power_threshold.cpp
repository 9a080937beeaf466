#include "radar_ndt/frontend/power_threshold.h"
#include "radar_ndt/se2.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <string>

namespace radar_ndt {
namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

double wrap2Pi(double a) {
  a = std::fmod(a, kTwoPi);
  return a < 0 ? a + kTwoPi : a;
}

/// Polar covariance (σr along the beam, σθ across it) at range r in direction (c, s) = (cos θ,
/// sin θ), through the Jacobian.
void setPolarCovariance(PointRadar& p, double r, double c, double s, double sigma_r, double sigma_theta,
                        double extra_var) {
  const double vr = sigma_r * sigma_r, vt = r * r * sigma_theta * sigma_theta;
  p.cov_xx = static_cast<float>(c * c * vr + s * s * vt + extra_var);
  p.cov_xy = static_cast<float>(c * s * (vr - vt));
  p.cov_yy = static_cast<float>(s * s * vr + c * c * vt + extra_var);
}

/// Maps a vehicle-frame angle to the two azimuth rows around it and the weight of the second.
class AzimuthLookup {
 public:
  explicit AzimuthLookup(const PolarScan& scan) : n_(scan.azimuths) {
    order_.resize(n_);
    std::iota(order_.begin(), order_.end(), 0);
    angle_.resize(n_);
    for (int a = 0; a < n_; ++a) angle_[a] = wrap2Pi(scan.angle[a]);
    std::sort(order_.begin(), order_.end(), [&](int i, int j) { return angle_[i] < angle_[j]; });
    sorted_.resize(n_);
    for (int k = 0; k < n_; ++k) sorted_[k] = angle_[order_[k]];
    table_size_ = 8 * n_;
    table_.resize(table_size_);
    int k = -1;  // largest k with sorted_[k] <= bin start (−1: before the first)
    for (int t = 0; t < table_size_; ++t) {
      const double start = kTwoPi * t / table_size_;
      while (k + 1 < n_ && sorted_[k + 1] <= start) ++k;
      table_[t] = k;
    }
  }

  /// θ in [0, 2π): rows a0, a1 = next(a0) and weight w of a1.
  void find(double theta, int& a0, int& a1, float& w) const {
    int t = static_cast<int>(theta * table_size_ / kTwoPi);
    t = std::min(std::max(t, 0), table_size_ - 1);
    int k = table_[t];
    while (k + 1 < n_ && sorted_[k + 1] <= theta) ++k;
    // k in [−1, n−1]: between sorted_[k] and sorted_[k+1], wrapping around 2π.
    const int k0 = k < 0 ? n_ - 1 : k;
    const int k1 = k0 + 1 == n_ ? 0 : k0 + 1;
    double lo = sorted_[k0], hi = sorted_[k1];
    if (k < 0) lo -= kTwoPi;
    if (k + 1 >= n_) hi += kTwoPi;
    const double span = hi - lo;
    w = span > 0 ? static_cast<float>((theta - lo) / span) : 0.0f;
    a0 = order_[k0];
    a1 = order_[k1];
  }

  /// The row after row `a` in angle order (wrapping): the a1 of every pixel whose a0 is `a`.
  std::vector<std::uint16_t> nextRows() const {
    std::vector<std::uint16_t> next(n_);
    for (int k = 0; k < n_; ++k) next[order_[k]] = static_cast<std::uint16_t>(order_[k + 1 == n_ ? 0 : k + 1]);
    return next;
  }

 private:
  int n_;
  std::vector<int> order_;
  std::vector<double> angle_, sorted_;
  int table_size_ = 0;
  std::vector<int> table_;
};

}  // namespace

struct PowerThreshold::Geometry {
  int bins = 0;
  double range_resolution = 0.0, range_offset_bins = 0.0;
  CartesianImage layout;
  // Bilinear sampling of each pixel inside the ring, valid for scans with these azimuth angles (a
  // dataset's angles repeat from scan to scan, so this is computed once per sequence). Pixels are
  // grouped by the polar block they sample, rows a0 and next[a0] × bins b0 and b0 + 1: block
  // (a0, b0) holds pixels block_start[a0·blocks_per_row + b0] .. block_start[… + 1] − 1, in raster
  // order within it. A block whose four samples are all at or below the threshold cannot give a
  // point (bilinear values never exceed their largest sample), so compute() skips it whole.
  std::vector<double> angles;
  int blocks_per_row = 0;
  std::vector<std::uint16_t> next;         ///< per azimuth row: the row after it in angle order
  std::vector<std::uint32_t> block_start;  ///< azimuths · blocks_per_row + 1 offsets
  std::vector<std::uint32_t> pixel;        ///< row · size + col
  std::vector<float> wa;                   ///< weight of row next[a0]
  std::vector<float> wb;                   ///< weight of bin b0 + 1
};

void PowerThresholdOptions::validate() const {
  checkFields(*this, "PowerThresholdOptions");
  if (!(max_range > min_range))
    throw std::invalid_argument("PowerThresholdOptions: max_range must exceed min_range (" + std::to_string(min_range) +
                                " m), got " + std::to_string(max_range));
}

/// The geometry last built, behind a lock: a thread that finds it matching its scan takes a
/// reference to it; a new layout replaces it without freeing what another thread still reads.
struct PowerThreshold::GeometryCache {
  std::mutex mutex;
  std::shared_ptr<const Geometry> geometry;
};

PowerThreshold::PowerThreshold(const PowerThresholdOptions& options)
    : options_(options), cache_(std::make_shared<GeometryCache>()) {
  options_.validate();
}

std::shared_ptr<const PowerThreshold::Geometry> PowerThreshold::geometry(const PolarScan& scan) const {
  if (scan.azimuths < 2 || scan.bins < 2)
    throw std::invalid_argument("PowerThreshold: scan has fewer than 2 azimuths or bins");
  if (scan.azimuths > 65535) throw std::invalid_argument("PowerThreshold: more than 65535 azimuths");
  // Built under the lock: a layout changes once a sequence (the first scan), so the others wait once.
  std::lock_guard<std::mutex> lock(cache_->mutex);
  const std::shared_ptr<const Geometry>& cached = cache_->geometry;
  if (cached && cached->bins == scan.bins && cached->range_resolution == scan.range_resolution &&
      cached->range_offset_bins == scan.range_offset_bins && cached->angles == scan.angle)
    return cached;
  cache_->geometry = buildGeometry(scan);
  return cache_->geometry;
}

std::shared_ptr<const PowerThreshold::Geometry> PowerThreshold::buildGeometry(const PolarScan& scan) const {
  auto g = std::make_shared<Geometry>();
  g->bins = scan.bins;
  g->range_resolution = scan.range_resolution;
  g->range_offset_bins = scan.range_offset_bins;
  g->angles = scan.angle;
  CartesianImage& L = g->layout;
  L.resolution = options_.cartesian_resolution;
  L.size = 2 * static_cast<int>(std::ceil(options_.max_range / L.resolution));
  const double max_r = std::min(options_.max_range, scan.maxRange());
  const AzimuthLookup lookup(scan);
  g->next = lookup.nextRows();
  const int last_bin = scan.bins - 1;
  // Blocks per row: up to the last bin the ring reaches (b0 <= bins − 2), not the whole row.
  g->blocks_per_row = std::min(last_bin, static_cast<int>(max_r / scan.range_resolution - scan.range_offset_bins) + 2);
  g->blocks_per_row = std::max(g->blocks_per_row, 1);
  struct Sample {
    std::uint32_t pixel, block;
    float wa, wb;
  };
  std::vector<Sample> samples;
  for (int r = 0; r < L.size; ++r) {
    for (int c = 0; c < L.size; ++c) {
      const double x = L.x(r), y = L.y(c);
      const double range = std::hypot(x, y);
      if (range < options_.min_range || range > max_r) continue;
      const float fb = std::max(0.0f, static_cast<float>(range / scan.range_resolution - scan.range_offset_bins));
      int a0, a1;
      float w;
      lookup.find(wrap2Pi(std::atan2(y, x)), a0, a1, w);
      const int b0 = std::min({static_cast<int>(fb), last_bin - 1, g->blocks_per_row - 1});
      samples.push_back({static_cast<std::uint32_t>(r * L.size + c),
                         static_cast<std::uint32_t>(a0 * g->blocks_per_row + b0), w, std::min(1.0f, fb - b0)});
    }
  }
  // Counting sort by block (stable: raster order within a block).
  const std::size_t n_blocks = static_cast<std::size_t>(scan.azimuths) * g->blocks_per_row;
  g->block_start.assign(n_blocks + 1, 0);
  for (const Sample& x : samples) ++g->block_start[x.block + 1];
  for (std::size_t b = 0; b < n_blocks; ++b) g->block_start[b + 1] += g->block_start[b];
  std::vector<std::uint32_t> fill(g->block_start.begin(), g->block_start.end() - 1);
  g->pixel.resize(samples.size());
  g->wa.resize(samples.size());
  g->wb.resize(samples.size());
  for (const Sample& x : samples) {
    const std::uint32_t i = fill[x.block]++;
    g->pixel[i] = x.pixel;
    g->wa[i] = x.wa;
    g->wb[i] = x.wb;
  }
  return g;
}

namespace {
/// hot[b] = 1 when block b of rows r0, r1 (bins b, b + 1 of both) has a sample above `limit`,
/// else 0, for b < n. Separate pointers and a plain loop, so the compiler vectorises it.
void markHotBlocks(const std::uint8_t* __restrict r0, const std::uint8_t* __restrict r1, int n, std::uint8_t limit,
                   std::uint8_t* __restrict hot) {
  for (int b = 0; b < n; ++b) {
    const std::uint8_t m0 = r0[b] > r0[b + 1] ? r0[b] : r0[b + 1];
    const std::uint8_t m1 = r1[b] > r1[b + 1] ? r1[b] : r1[b + 1];
    hot[b] = static_cast<std::uint8_t>((m0 > m1 ? m0 : m1) > limit);
  }
}

inline int countTrailingZeros(std::uint64_t x) {  // x != 0
#if defined(__GNUC__) || defined(__clang__)
  return __builtin_ctzll(x);
#else
  int n = 0;
  while (!(x & 1u)) {
    x >>= 1;
    ++n;
  }
  return n;
#endif
}

/// Calls f(i, r0 + b0, r1 + b0, a0) for the geometry's pixels i of every block (a0, b0), row by
/// row (r0, r1: rows a0 and next[a0]); with `threshold` (power 0..1) only for blocks with a sample
/// above it. The block test runs over a whole row at a time (byte maxima the compiler vectorises),
/// then visits the marked blocks, found eight flags at a time.
template <typename G, typename F>
void forEachBlockPixel(const G& g, const PolarScan& scan, const float* threshold, F&& f) {
  const int nb = g.blocks_per_row;
  // A sample v passes when v / 255 > threshold, exactly as samplePixel's result is tested; that
  // is monotone in v, so a block can pass iff its largest sample exceeds `last_failing`.
  int last_failing = -1;
  if (threshold)
    while (last_failing < 255 && !(static_cast<float>(last_failing + 1) * (1.0f / 255.0f) > *threshold)) ++last_failing;
  std::vector<std::uint8_t> hot(static_cast<std::size_t>(nb) + 8, 0);  // zero padding past nb
  for (int a = 0; a < scan.azimuths; ++a) {
    const std::uint32_t* start = g.block_start.data() + static_cast<std::size_t>(a) * nb;
    const std::uint8_t* r0 = scan.row(a);
    const std::uint8_t* r1 = scan.row(g.next[a]);
    auto visit = [&](int b) {
      for (std::uint32_t i = start[b], end = start[b + 1]; i < end; ++i) f(i, r0 + b, r1 + b, a);
    };
    if (!threshold) {
      for (int b = 0; b < nb; ++b) visit(b);
      continue;
    }
    if (last_failing >= 255) continue;
    if (last_failing < 0) {  // every sample passes
      for (int b = 0; b < nb; ++b) visit(b);
      continue;
    }
    markHotBlocks(r0, r1, nb, static_cast<std::uint8_t>(last_failing), hot.data());
    for (int b = 0; b < nb; b += 8) {
      std::uint64_t word;  // one flag byte (0 or 1) per block b .. b + 7
      std::memcpy(&word, hot.data() + b, sizeof(word));
      for (; word != 0; word &= word - 1) visit(b + (countTrailingZeros(word) >> 3));
    }
  }
}

/// Bilinear power (0..1) of geometry pixel i between rows r0, r1 (each at the pixel's bin b0).
template <typename G>
inline float samplePixel(const G& g, const std::uint8_t* r0, const std::uint8_t* r1, std::uint32_t i) {
  const float wb = g.wb[i];
  const float v0 = r0[0] + wb * (r0[1] - r0[0]);
  const float v1 = r1[0] + wb * (r1[1] - r1[0]);
  return (v0 + g.wa[i] * (v1 - v0)) * (1.0f / 255.0f);
}
}  // namespace

CartesianImage PowerThreshold::cartesianImage(const PolarScan& scan) const {
  const std::shared_ptr<const Geometry> shared = geometry(scan);
  const Geometry& g = *shared;
  CartesianImage img = g.layout;
  img.power.assign(static_cast<std::size_t>(img.size) * img.size, -1.0f);
  forEachBlockPixel(g, scan, nullptr, [&](std::uint32_t i, const std::uint8_t* r0, const std::uint8_t* r1, int) {
    img.power[g.pixel[i]] = samplePixel(g, r0, r1, i);
  });
  return img;
}

void PowerThreshold::compute(const PolarScan& scan, pcl::PointCloud<PointRadar>& out) const {
  out.clear();
  out.header.stamp = static_cast<std::uint64_t>(scan.stamp);
  const double sigma_theta = options_.beam_width_deg * kPi / 180.0 / 2.355;  // FWHM → σ
  const double sigma_r = scan.range_resolution;
  if (options_.cartesian) {
    // The image is never materialised: each pixel of a block that can pass is sampled and kept if
    // above the threshold. Points come out block by block (azimuth row, then range bin).
    const std::shared_ptr<const Geometry> shared = geometry(scan);
    const Geometry& g = *shared;
    const CartesianImage& img = g.layout;
    const double pixel_var = img.resolution * img.resolution / 12.0;
    const float threshold = options_.threshold;
    forEachBlockPixel(
        g, scan, &threshold, [&](std::uint32_t i, const std::uint8_t* r0, const std::uint8_t* r1, int a0) {
          const float p = samplePixel(g, r0, r1, i);
          if (!(p > threshold)) return;
          const int row = static_cast<int>(g.pixel[i]) / img.size, col = static_cast<int>(g.pixel[i]) % img.size;
          const double x = img.x(row), y = img.y(col);
          const double range = std::sqrt(x * x + y * y);  // > 0: min_range >= 0 and pixel centres are off the origin
          PointRadar pt;
          pt.x = static_cast<float>(x);
          pt.y = static_cast<float>(y);
          pt.z = 0.0f;
          pt.power = p;
          setPolarCovariance(pt, range, x / range, y / range, sigma_r, sigma_theta, pixel_var);
          const int a = g.wa[i] < 0.5f ? a0 : g.next[a0];
          pt.time_offset = static_cast<float>((scan.stamp_us[a] - scan.stamp) * 1e-6);
          out.push_back(pt);
        });
  } else {
    for (int a = 0; a < scan.azimuths; ++a) {
      const std::uint8_t* row = scan.row(a);
      const double c = std::cos(scan.angle[a]), s = std::sin(scan.angle[a]);
      const float dt = static_cast<float>((scan.stamp_us[a] - scan.stamp) * 1e-6);
      const auto threshold255 = options_.threshold * 255.0f;
      for (int b = 0; b < scan.bins; ++b) {
        if (!(row[b] > threshold255)) continue;
        const double range = scan.rangeOf(b);
        if (range < options_.min_range || range > options_.max_range) continue;
        PointRadar pt;
        pt.x = static_cast<float>(range * c);
        pt.y = static_cast<float>(range * s);
        pt.z = 0.0f;
        pt.power = row[b] / 255.0f;
        setPolarCovariance(pt, range, c, s, sigma_r, sigma_theta, 0.0);
        pt.time_offset = dt;
        out.push_back(pt);
      }
    }
  }
  out.width = static_cast<std::uint32_t>(out.size());
  out.height = 1;
  out.is_dense = true;
}

PowerStatistics powerStatistics(const CartesianImage& image, float threshold) {
  PowerStatistics s;
  std::vector<float> v;
  v.reserve(image.power.size());
  for (float p : image.power)
    if (p >= 0.0f) v.push_back(p);
  s.pixels = v.size();
  if (v.empty()) return s;
  std::vector<float> excess;
  for (float p : v)
    if (p > threshold) excess.push_back(p - threshold);
  s.points = excess.size();
  s.fraction_above = static_cast<double>(s.points) / s.pixels;
  auto pct = [](std::vector<float>& x, double q) {
    if (x.empty()) return 0.0;
    const std::size_t k = std::min(x.size() - 1, static_cast<std::size_t>(q * (x.size() - 1) + 0.5));
    std::nth_element(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(k), x.end());
    return static_cast<double>(x[k]);
  };
  s.p50 = pct(v, 0.50);
  s.p90 = pct(v, 0.90);
  s.p99 = pct(v, 0.99);
  s.excess_p50 = pct(excess, 0.50);
  s.excess_p90 = pct(excess, 0.90);
  s.excess_p99 = pct(excess, 0.99);
  return s;
}

PowerStatistics medianStatistics(std::vector<PowerStatistics> scans) {
  PowerStatistics m;
  if (scans.empty()) return m;
  auto median = [&](auto field) {
    std::vector<double> v;
    for (const auto& s : scans) v.push_back(static_cast<double>(s.*field));
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  m.pixels = static_cast<std::size_t>(median(&PowerStatistics::pixels));
  m.fraction_above = median(&PowerStatistics::fraction_above);
  m.p50 = median(&PowerStatistics::p50);
  m.p90 = median(&PowerStatistics::p90);
  m.p99 = median(&PowerStatistics::p99);
  m.excess_p50 = median(&PowerStatistics::excess_p50);
  m.excess_p90 = median(&PowerStatistics::excess_p90);
  m.excess_p99 = median(&PowerStatistics::excess_p99);
  m.points = static_cast<std::size_t>(median(&PowerStatistics::points));
  return m;
}

}  // namespace radar_ndt
