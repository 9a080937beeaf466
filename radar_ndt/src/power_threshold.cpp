#include "radar_ndt/power_threshold.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace radar_ndt {
namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

double wrap2Pi(double a) {
  a = std::fmod(a, kTwoPi);
  return a < 0 ? a + kTwoPi : a;
}

/// Polar covariance (σr along the beam, σθ across it) at range r and angle θ, through the Jacobian.
void setPolarCovariance(PointRadar& p, double r, double theta, double sigma_r, double sigma_theta, double extra_var) {
  const double c = std::cos(theta), s = std::sin(theta);
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

  /// θ in [0, 2π): rows a0, a1 and weight w of a1.
  void find(double theta, int& a0, int& a1, float& w) const {
    int t = static_cast<int>(theta * table_size_ / kTwoPi);
    t = std::min(std::max(t, 0), table_size_ - 1);
    int k = table_[t];
    while (k + 1 < n_ && sorted_[k + 1] <= theta) ++k;
    // k in [−1, n−1]: between sorted_[k] and sorted_[k+1], wrapping around 2π.
    const int k0 = k < 0 ? n_ - 1 : k;
    const int k1 = k + 1 >= n_ ? 0 : k + 1;
    double lo = sorted_[k0], hi = sorted_[k1];
    double th = theta;
    if (k < 0) lo -= kTwoPi;
    if (k + 1 >= n_) hi += kTwoPi;
    const double span = hi - lo;
    w = span > 0 ? static_cast<float>((th - lo) / span) : 0.0f;
    a0 = order_[k0];
    a1 = order_[k1];
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
  std::vector<std::uint32_t> pixel;  ///< pixels inside the ring
  std::vector<float> theta;          ///< its angle in [0, 2π)
  // Bilinear sampling of each pixel, valid for scans with these azimuth angles (a dataset's
  // angles repeat from scan to scan, so this is computed once per sequence).
  std::vector<double> angles;
  std::vector<std::uint16_t> a0, a1;  ///< the azimuth rows around the pixel
  std::vector<float> wa;              ///< weight of a1
  std::vector<std::int32_t> b0;       ///< the lower range bin
  std::vector<float> wb;              ///< weight of b0 + 1
};

PowerThreshold::PowerThreshold(const PowerThresholdOptions& options) : options_(options) {
  if (!(options_.cartesian_resolution > 0) || !(options_.max_range > 0) || !(options_.min_range >= 0) ||
      options_.min_range >= options_.max_range || !std::isfinite(options_.threshold) || !(options_.beam_width_deg > 0))
    throw std::invalid_argument("PowerThreshold: resolution and range must be positive, min_range < max_range, "
                                "threshold finite, beam width positive");
}

const PowerThreshold::Geometry& PowerThreshold::geometry(const PolarScan& scan) const {
  if (scan.azimuths < 2 || scan.bins < 2) throw std::invalid_argument("PowerThreshold: scan has fewer than 2 azimuths or bins");
  if (scan.azimuths > 65535) throw std::invalid_argument("PowerThreshold: more than 65535 azimuths");
  if (geometry_ && geometry_->bins == scan.bins && geometry_->range_resolution == scan.range_resolution &&
      geometry_->range_offset_bins == scan.range_offset_bins && geometry_->angles == scan.angle)
    return *geometry_;
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
  const int last_bin = scan.bins - 1;
  for (int r = 0; r < L.size; ++r) {
    for (int c = 0; c < L.size; ++c) {
      const double x = L.x(r), y = L.y(c);
      const double range = std::hypot(x, y);
      if (range < options_.min_range || range > max_r) continue;
      g->pixel.push_back(static_cast<std::uint32_t>(r * L.size + c));
      const float fb = std::max(0.0f, static_cast<float>(range / scan.range_resolution - scan.range_offset_bins));
      const float theta = static_cast<float>(wrap2Pi(std::atan2(y, x)));
      g->theta.push_back(theta);
      int a0, a1;
      float w;
      lookup.find(theta, a0, a1, w);
      int b0 = static_cast<int>(fb);
      if (b0 >= last_bin) b0 = last_bin - 1;
      g->a0.push_back(static_cast<std::uint16_t>(a0));
      g->a1.push_back(static_cast<std::uint16_t>(a1));
      g->wa.push_back(w);
      g->b0.push_back(b0);
      g->wb.push_back(std::min(1.0f, fb - b0));
    }
  }
  geometry_ = g;
  return *geometry_;
}

namespace {
/// Bilinear power (0..1) of geometry pixel i.
template <typename G>
inline float samplePixel(const G& g, const PolarScan& scan, std::size_t i) {
  const std::uint8_t* r0 = scan.row(g.a0[i]) + g.b0[i];
  const std::uint8_t* r1 = scan.row(g.a1[i]) + g.b0[i];
  const float wb = g.wb[i];
  const float v0 = r0[0] + wb * (r0[1] - r0[0]);
  const float v1 = r1[0] + wb * (r1[1] - r1[0]);
  return (v0 + g.wa[i] * (v1 - v0)) * (1.0f / 255.0f);
}
}  // namespace

CartesianImage PowerThreshold::cartesianImage(const PolarScan& scan) const {
  const Geometry& g = geometry(scan);
  CartesianImage img = g.layout;
  img.power.assign(static_cast<std::size_t>(img.size) * img.size, -1.0f);
  for (std::size_t i = 0; i < g.pixel.size(); ++i) img.power[g.pixel[i]] = samplePixel(g, scan, i);
  return img;
}

void PowerThreshold::compute(const PolarScan& scan, pcl::PointCloud<PointRadar>& out) const {
  out.clear();
  out.header.stamp = static_cast<std::uint64_t>(scan.stamp);
  const double sigma_theta = options_.beam_width_deg * M_PI / 180.0 / 2.355;  // FWHM → σ
  const double sigma_r = scan.range_resolution;
  if (options_.cartesian) {
    // The image is never materialised: each pixel is sampled and kept if above the threshold.
    const Geometry& g = geometry(scan);
    const CartesianImage& img = g.layout;
    const double pixel_var = img.resolution * img.resolution / 12.0;
    for (std::size_t i = 0; i < g.pixel.size(); ++i) {
      const float p = samplePixel(g, scan, i);
      if (!(p > options_.threshold)) continue;
      const int row = static_cast<int>(g.pixel[i]) / img.size, col = static_cast<int>(g.pixel[i]) % img.size;
      PointRadar pt;
      pt.x = static_cast<float>(img.x(row));
      pt.y = static_cast<float>(img.y(col));
      pt.z = 0.0f;
      pt.power = p;
      const double range = std::hypot(img.x(row), img.y(col));
      setPolarCovariance(pt, range, g.theta[i], sigma_r, sigma_theta, pixel_var);
      const int a = g.wa[i] < 0.5f ? g.a0[i] : g.a1[i];
      pt.time_offset = static_cast<float>((scan.stamp_us[a] - scan.stamp) * 1e-6);
      out.push_back(pt);
    }
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
        setPolarCovariance(pt, range, scan.angle[a], sigma_r, sigma_theta, 0.0);
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
  for (float p : v) s.points += p > threshold;
  s.fraction_above = static_cast<double>(s.points) / s.pixels;
  auto pct = [&](double q) {
    const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return static_cast<double>(v[k]);
  };
  s.p50 = pct(0.50);
  s.p90 = pct(0.90);
  s.p99 = pct(0.99);
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
  m.points = static_cast<std::size_t>(median(&PowerStatistics::points));
  return m;
}

}  // namespace radar_ndt
