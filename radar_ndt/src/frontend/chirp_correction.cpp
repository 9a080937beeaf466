#include "radar_ndt/frontend/chirp_correction.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <Eigen/Dense>

#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace {

// The displacement pattern g(θ) = −(u_x cos θ + u_y sin θ) of static scenery.
double displacement(const Eigen::Vector2d& u, double angle) {
  return -(u.x() * std::cos(angle) + u.y() * std::sin(angle));
}

struct PairShift {
  double angle = 0;  ///< mean bearing of the pair
  double g = 0;      ///< observed g(θ) (m)
};

// The shift (bins, sub-bin) of row b's content relative to row a's, from the strongest bins of a
// correlated against b, or false without a clear peak. `b_centred` is row b over the whole band
// with its mean removed, padded by `max_lag` zeros on both sides (no bounds checks in the loop).
// Storage one scan's pairs reuse (the estimate runs on every scan with chirp types).
struct PairScratch {
  std::vector<std::uint8_t> sorted;
  std::vector<int> bins;  // offsets into b_centred at lag −max_lag
  std::vector<float> weights;
  std::vector<float> c;
};

bool relativeShift(const std::uint8_t* ra, const std::vector<float>& b_centred, int lo, int hi, int max_lag,
                   double top_share, double min_peak, PairScratch& scratch, double* lag) {
  double mean_a = 0;
  for (int i = lo; i < hi; ++i) mean_a += ra[i];
  mean_a /= hi - lo;
  std::vector<std::uint8_t>& sorted = scratch.sorted;
  sorted.assign(ra + lo, ra + hi);
  const std::size_t keep = std::max<std::size_t>(8, static_cast<std::size_t>(top_share * sorted.size()));
  std::nth_element(sorted.begin(), sorted.end() - static_cast<std::ptrdiff_t>(keep), sorted.end());
  const double level = std::max(static_cast<double>(*(sorted.end() - static_cast<std::ptrdiff_t>(keep))), mean_a + 1.0);
  std::vector<int>& bins = scratch.bins;
  std::vector<float>& weights = scratch.weights;
  bins.clear();
  weights.clear();
  double norm_a = 0;
  for (int i = lo; i < hi; ++i)
    if (ra[i] >= level) {
      bins.push_back(i - lo);
      weights.push_back(static_cast<float>(ra[i] - mean_a));
      norm_a += (ra[i] - mean_a) * (ra[i] - mean_a);
    }
  if (bins.size() < 8) return false;
  const int lags = 2 * max_lag + 1;
  std::vector<float>& c = scratch.c;
  c.assign(static_cast<std::size_t>(lags), 0.0f);
  for (std::size_t j = 0; j < bins.size(); ++j) {
    const float w = weights[j];
    const float* row = b_centred.data() + bins[j];  // b_centred[bins[j] + max_lag + k] is lag k
    for (int k = 0; k < lags; ++k) c[static_cast<std::size_t>(k)] += w * row[k];
  }
  const auto best = std::max_element(c.begin(), c.end());
  const int k = static_cast<int>(best - c.begin());
  if (k == 0 || k == lags - 1) return false;  // at the edge of the search: no peak
  // How clear: the peak against the energy of b over a's bins at that lag.
  double norm_b = 0;
  for (int i : bins)
    norm_b +=
        static_cast<double>(b_centred[static_cast<std::size_t>(i + k)]) * b_centred[static_cast<std::size_t>(i + k)];
  if (!(*best > min_peak * std::sqrt(norm_a * norm_b))) return false;
  const double l = c[static_cast<std::size_t>(k - 1)], m = *best, r = c[static_cast<std::size_t>(k + 1)];
  const double denom = l - 2 * m + r;
  *lag = (k - max_lag) + (denom < 0 ? 0.5 * (l - r) / denom : 0.0);
  return true;
}

// Least squares of g = −(u_x cos θ + u_y sin θ) over `pairs` (weights 0 or 1).
Eigen::Vector2d fit(const std::vector<PairShift>& pairs, const std::vector<bool>& use) {
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (!use[i]) continue;
    const Eigen::Vector2d j(-std::cos(pairs[i].angle), -std::sin(pairs[i].angle));
    A += j * j.transpose();
    b += j * pairs[i].g;
  }
  return A.ldlt().solve(b);
}

}  // namespace

void ChirpCorrectionOptions::validate() const {
  checkFields(*this, "ChirpCorrectionOptions");
  if (!(max_range > min_range)) throw std::invalid_argument("ChirpCorrectionOptions: max_range must exceed min_range");
}

ChirpShiftEstimate estimateChirpShift(const PolarScan& scan, const ChirpCorrectionOptions& options) {
  options.validate();
  ChirpShiftEstimate out;
  if (scan.chirp_up.size() != static_cast<std::size_t>(scan.azimuths) || scan.azimuths < 2) return out;
  const double res = scan.range_resolution;
  const int lo =
      std::clamp(static_cast<int>(std::ceil(options.min_range / res - scan.range_offset_bins)), 0, scan.bins);
  const int hi =
      std::clamp(static_cast<int>(std::floor(options.max_range / res - scan.range_offset_bins)), lo, scan.bins);
  const int max_lag = std::max(1, static_cast<int>(std::ceil(2.0 * options.max_shift / res)));
  if (hi - lo < 4 * max_lag) return out;
  std::vector<PairShift> pairs;
  std::vector<float> b_centred(static_cast<std::size_t>(hi - lo + 2 * max_lag));
  PairScratch scratch;
  // Every neighbouring pair: (0, 1) is down then up, (1, 2) up then down, so the change of a
  // structure's range with the bearing between two azimuths, the same in both, cancels in the fit.
  for (int a = 0; a + 1 < scan.azimuths; ++a) {
    const int s_a = scan.chirp_up[a] ? 1 : -1, s_b = scan.chirp_up[a + 1] ? 1 : -1;
    if (s_a == s_b) continue;
    const std::uint8_t* rb = scan.row(a + 1);
    double mean_b = 0;
    for (int i = lo; i < hi; ++i) mean_b += rb[i];
    mean_b /= hi - lo;
    std::fill(b_centred.begin(), b_centred.end(), 0.0f);
    for (int i = std::max(0, lo - max_lag); i < std::min(scan.bins, hi + max_lag); ++i)
      b_centred[static_cast<std::size_t>(i - lo + max_lag)] = static_cast<float>(rb[i] - mean_b);
    double lag = 0;
    if (!relativeShift(scan.row(a), b_centred, lo, hi, max_lag, options.top_share, options.min_peak, scratch, &lag))
      continue;
    // Row b's content lies `lag` bins beyond row a's: (s_b − s_a) · g(θ) = lag · res.
    const double da = scan.angle[a + 1] - scan.angle[a];
    const double mid = scan.angle[a] + 0.5 * std::remainder(da, 2.0 * kPi);
    pairs.push_back({mid, lag * res / (s_b - s_a)});
  }
  if (static_cast<int>(pairs.size()) < options.min_pairs) return out;
  std::vector<bool> use(pairs.size(), true);
  Eigen::Vector2d u = fit(pairs, use);
  // Once more without the pairs far off the first fit (3 median absolute residuals, at least a bin).
  std::vector<double> residual(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) residual[i] = std::abs(pairs[i].g - displacement(u, pairs[i].angle));
  std::vector<double> sorted = residual;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double cut = std::max(3.0 * sorted[sorted.size() / 2], res);
  int kept = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) kept += (use[i] = residual[i] <= cut) ? 1 : 0;
  if (kept < options.min_pairs) return out;
  u = fit(pairs, use);
  double ss = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i)
    if (use[i]) ss += std::pow(pairs[i].g - displacement(u, pairs[i].angle), 2);
  out.valid = true;
  out.u = u;
  out.pairs = kept;
  out.rms = std::sqrt(ss / kept);
  return out;
}

void correctChirpShift(PolarScan& scan, const Eigen::Vector2d& u, double max_range) {
  if (scan.chirp_up.size() != static_cast<std::size_t>(scan.azimuths)) return;
  // The bins up to max_range, and one more for the front-end's interpolation.
  const double last = max_range / scan.range_resolution - scan.range_offset_bins + 2.0;
  const int bins = last >= scan.bins ? scan.bins : std::max(0, static_cast<int>(std::ceil(last)));
  shiftRanges(
      scan, [&](int a) { return -(scan.chirp_up[a] ? 1.0 : -1.0) * displacement(u, scan.angle[a]); }, bins);
}

ChirpShiftEstimate correctChirps(PolarScan& scan, const ChirpCorrectionOptions& options, double max_range) {
  if (!options.enabled || scan.chirp_up.empty()) return {};
  const ChirpShiftEstimate e = estimateChirpShift(scan, options);
  if (e.valid) correctChirpShift(scan, e.u, max_range);
  return e;
}

}  // namespace radar_ndt
