// The simulator's scanning radar: one Navtech sweep rendered into a polar scan (Oxford
// conventions), pass by pass: ray casting with the beam and range response, the scatterer field,
// the antenna's azimuth sidelobes, then noise, clutter, speckle and the display (docs/simulator.md).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/sim/radar_sim.h"
#include "scan_models.h"
#include "sim_common.h"
#include "sim_random.h"

namespace radar_ndt {
namespace sim {

using detail::dbToLinear;
using detail::kDeg;
using detail::toMicros;

namespace {

using namespace detail;

/// One scan being rendered: the per-scan constants (beam, range response, noise by range), the
/// received signal of every (azimuth, bin) before the display, and the passes that build it.
class ScanRenderer {
 public:
  ScanRenderer(const World& world, const SimTrajectory& ego, double t, std::uint64_t seed, const ScanningOptions& o,
               PolarScan& scan)
      : world_(world),
        ego_(ego),
        t_(t),
        seed_(seed),
        o_(o),
        scan_(scan),
        A_(o.azimuths),
        B_(o.bins),
        res_(o.range_resolution),
        offset_(o.range_offset_bins) {
    prepareScan();
    prepareBeam();
    prepareRangeResponse();
    prepareNoise();
  }

  /// Pass 1, per azimuth: the received signal (linear power over the noise mean at 0 m) from ray
  /// casting, with the range response; where the central ray is stopped and where it leaves the road.
  void castSweep() {
    for (int a = 0; a < A_; ++a) castAzimuth(a);
  }
  /// Pass 1b: the scatterer field, splatted through the beam's main lobe (Gaussian in azimuth) and
  /// the range response; each is seen from the pose of the azimuth that looks at it (motion
  /// distortion), attenuated behind that azimuth's first opaque surface.
  void addScatterers();
  /// Pass 2: antenna sidelobes in azimuth (circular over the sweep).
  void addAzimuthSidelobes();
  /// Pass 3, per azimuth: leakage, noise, ground clutter, speckle and the display.
  void display(Random& rng);

 private:
  void prepareScan();
  void prepareBeam();
  void prepareRangeResponse();
  void prepareNoise();
  void castAzimuth(int a);
  void castBeamRay(int j, double angle, const Eigen::Vector2d& origin, double ta, double* signal, double& occluded);
  void addGhost(const Hit& h, double angle, const Eigen::Vector2d& origin, double ta, double* signal);
  void addBehindOccluder(int j, double angle, const Eigen::Vector2d& origin, double ta, double occluded,
                         double* signal);
  void addRangeSidelobes(double* signal);
  /// Adds a return of linear power `p` spread over [r, r + depth] and blurred by the range PSF.
  void addReturn(double* signal, double r, double depth, double p) const;
  /// Power (linear, over the noise mean) of a hit at range r, before the beam gain.
  double hitPower(const Hit& h, double r) const;
  int lookingAzimuth(const Eigen::Vector2d& p, Pose2& pose) const;
  void splatScatterer(const Scatterer& sc, int spread);
  std::uint8_t countsByte(Random& rng, double s, double mean, bool saturated) const;
  std::uint8_t logByte(Random& rng, double s, double mean, bool saturated, int b) const;

  const World& world_;
  const SimTrajectory& ego_;
  const double t_;
  const std::uint64_t seed_;
  const ScanningOptions& o_;
  PolarScan& scan_;
  const OxfordPolarOptions oxford_;
  const int A_, B_;
  const double res_, offset_;
  // Beam: sub-rays across ±0.9 beam widths with Gaussian two-way gains (σ = width / 2.355).
  double beam_sigma_ = 0;
  std::vector<double> ray_offset_, ray_gain_;
  double max_range_ = 0;
  Pose2 centre_ = Pose2::Zero();  ///< the mid-sweep pose
  std::vector<int> movers_;
  // The range response: the PSF, sidelobes, pedestal; returns over occluders, leakage, saturation.
  double sigma_ = 0, sidelobe_ = 0, side_decay_ = 0, pedestal_ = 0, pedestal_decay_ = 0, over_ = 0;
  bool pedestal_on_ = false, over_on_ = false;
  double leakage_ = 0, saturation_ = 0, leak_range_ = 0, clutter_ = 0;
  // The display: the knee of its compression, the tabulated exponentials of noise and speckle.
  double knee_lin_ = 0;
  const std::vector<float>& exp_table_ = exponentialTable();
  const std::vector<float>& exp_db_ = exponentialDbTable();
  // Per bin: the noise mean (dB and linear) and the range loss.
  std::vector<float> noise_db_;
  std::vector<double> noise_lin_, range_gain_;
  std::vector<double> forward_, backward_;  ///< the sidelobe recursions' scratch
  std::vector<Hit> hits_, bounce_, behind_;
  // Per azimuth and bin: the received signal; per azimuth: the central ray's first opaque
  // surface, the sensor's position and the beam's direction.
  std::vector<double> signal_all_;
  std::vector<double> occluded_at_;
  std::vector<Eigen::Vector2d> origins_, directions_;
};

void ScanRenderer::prepareScan() {
  scan_.azimuths = A_;
  scan_.bins = B_;
  scan_.range_resolution = res_;
  scan_.range_offset_bins = offset_;
  scan_.power.assign(static_cast<std::size_t>(A_) * B_, 0);
  scan_.angle.resize(A_);
  scan_.stamp_us.resize(A_);
  scan_.measured.assign(A_, 1);
  scan_.encoder.resize(A_);
  signal_all_.assign(static_cast<std::size_t>(A_) * B_, 0.0);
  occluded_at_.resize(A_);
  origins_.resize(A_);
  directions_.resize(A_);
}

void ScanRenderer::prepareBeam() {
  const double beam = o_.beam_width_deg * kDeg;
  beam_sigma_ = beam / 2.355;
  ray_offset_.resize(o_.beam_rays);
  ray_gain_.resize(o_.beam_rays);
  double gain_sum = 0.0;
  for (int j = 0; j < o_.beam_rays; ++j) {
    ray_offset_[j] = o_.beam_rays == 1 ? 0.0 : (static_cast<double>(j) / (o_.beam_rays - 1) - 0.5) * 1.8 * beam;
    ray_gain_[j] = std::exp(-0.5 * std::pow(ray_offset_[j] / beam_sigma_, 2));
    gain_sum += ray_gain_[j];
  }
  for (double& g : ray_gain_) g /= gain_sum;
  max_range_ = std::min(o_.max_range, (B_ - 1 + offset_) * res_);
  centre_ = ego_.at(t_ + 0.5 * o_.sweep_period);
  movers_ = world_.activeMovers(centre_.head<2>(), max_range_ + 5.0, t_ + 0.5 * o_.sweep_period);
}

void ScanRenderer::prepareRangeResponse() {
  sigma_ = std::max(o_.range_psf_sigma, 1e-3);
  sidelobe_ = dbToLinear(o_.range_sidelobe_db);
  side_decay_ = std::exp(-res_ / std::max(o_.range_sidelobe_length, 1e-3));
  pedestal_on_ = o_.range_pedestal_db > -199.0;
  pedestal_ = pedestal_on_ ? dbToLinear(o_.range_pedestal_db) : 0.0;
  pedestal_decay_ = std::exp(-res_ / o_.range_pedestal_length);
  over_on_ = o_.over_occluder_db > -199.0;
  over_ = over_on_ ? dbToLinear(o_.over_occluder_db) : 0.0;
  leakage_ = dbToLinear(o_.leakage_db);
  saturation_ = dbToLinear(o_.saturation_db);
  leak_range_ = 6.0 * o_.leakage_length;  // beyond it the leakage is below 1e-2.6 of its peak: not added
  knee_lin_ = o_.display_compression < 1.0 ? dbToLinear(o_.display_knee_db) : std::numeric_limits<double>::infinity();
  forward_.resize(B_);
  backward_.resize(B_);
}

void ScanRenderer::prepareNoise() {
  noise_db_.resize(B_);
  noise_lin_.resize(B_);
  range_gain_.resize(B_);
  clutter_ = o_.ground_clutter_cover > 0 ? dbToLinear(o_.ground_clutter_db) : 0.0;
  for (int b = 0; b < B_; ++b) {
    const double r = (b + offset_) * res_;
    noise_db_[b] = static_cast<float>(o_.noise_rise_db * std::min(r / max_range_, 1.0));
    noise_lin_[b] = dbToLinear(noise_db_[b]);
    range_gain_[b] = dbToLinear(-o_.range_loss_db_per_decade * std::log10(std::max(r, 10.0) / 10.0));
  }
}

void ScanRenderer::addReturn(double* signal, double r, double depth, double p) const {
  const double lo = r - 4.0 * sigma_, hi = r + depth + 4.0 * sigma_;
  const int b0 = std::max(0, static_cast<int>(std::floor(lo / res_ - offset_)));
  const int b1 = std::min(B_ - 1, static_cast<int>(std::ceil(hi / res_ - offset_)));
  const double norm = sigma_ * std::sqrt(2.0 * kPi) / std::max(depth, 1e-3);
  for (int b = b0; b <= b1; ++b) {
    const double x = (b + offset_) * res_ - r;
    const double k = depth > 1e-3 ? (phi(x / sigma_) - phi((x - depth) / sigma_)) * norm
                                  : std::exp(-0.5 * (x / sigma_) * (x / sigma_));
    signal[b] += p * k;
  }
}

double ScanRenderer::hitPower(const Hit& h, double r) const {
  const MaterialModel& m = materialModel(h.material);
  double db = o_.target_snr_db + m.reflect_db - o_.range_loss_db_per_decade * std::log10(std::max(r, 10.0) / 10.0);
  if (m.incidence_exp > 0) db += 10.0 * m.incidence_exp * std::log10(std::max(h.cos_incidence, 0.03));
  return dbToLinear(db);
}

void ScanRenderer::castAzimuth(int a) {
  scan_.encoder[a] =
      static_cast<std::uint16_t>((static_cast<long>(a) * oxford_.encoder_size / A_) % oxford_.encoder_size);
  scan_.angle[a] = oxford_.convention.toVehicleAngle(2.0 * kPi * scan_.encoder[a] / oxford_.encoder_size);
  const double ta = t_ + a * o_.sweep_period / A_;
  scan_.stamp_us[a] = toMicros(ta);  // re-based by the caller
  const Pose2 pose = ego_.at(ta);
  const Eigen::Vector2d origin = pose.head<2>();
  double* signal = &signal_all_[static_cast<std::size_t>(a) * B_];
  double occluded = max_range_;  // the central ray's first opaque surface (ground clutter stops there)
  for (int j = 0; j < o_.beam_rays; ++j)
    castBeamRay(j, pose.z() + scan_.angle[a] + ray_offset_[j], origin, ta, signal, occluded);
  addRangeSidelobes(signal);
  occluded_at_[a] = occluded;
  origins_[a] = origin;
  const double beam_angle = pose.z() + scan_.angle[a];
  directions_[a] = Eigen::Vector2d(std::cos(beam_angle), std::sin(beam_angle));
}

void ScanRenderer::castBeamRay(int j, double angle, const Eigen::Vector2d& origin, double ta, double* signal,
                               double& occluded) {
  world_.cast(origin, angle, ta, max_range_, movers_, hits_);
  double through = 1.0;  // share of the power left after transmissive hits
  const bool central = j == o_.beam_rays / 2;
  if (central && !hits_.empty() && materialModel(hits_.back().material).transmission <= 0.0)
    occluded = hits_.back().range;
  for (const Hit& h : hits_) {
    addReturn(signal, h.range, h.depth * o_.depth_scale, ray_gain_[j] * through * hitPower(h, h.range));
    through *= materialModel(h.material).transmission;
  }
  if (central && !hits_.empty() && o_.ghost_probability > 0) addGhost(hits_.back(), angle, origin, ta, signal);
  if (central && over_on_ && occluded < max_range_) addBehindOccluder(j, angle, origin, ta, occluded, signal);
}

void ScanRenderer::addGhost(const Hit& h, double angle, const Eigen::Vector2d& origin, double ta, double* signal) {
  // Multipath: the central ray bounces off a mirroring surface; what it meets next shows up
  // behind the mirror at the total path length.
  if (!mirrors(h.material) || !(h.cos_incidence > 0.25) || !specular(seed_, h.id, o_.ghost_probability)) return;
  const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
  const Eigen::Vector2d m = d - 2.0 * d.dot(h.normal) * h.normal;
  const Eigen::Vector2d p = origin + h.range * d + 0.05 * m;
  world_.cast(p, std::atan2(m.y(), m.x()), ta, max_range_ - h.range, movers_, bounce_);
  if (bounce_.empty()) return;
  const Hit& g = bounce_.back();
  const double r = h.range + g.range;
  if (r < max_range_)
    addReturn(signal, r, g.depth * o_.depth_scale, hitPower(g, r) * dbToLinear(-o_.ghost_attenuation_db));
}

void ScanRenderer::addBehindOccluder(int j, double angle, const Eigen::Vector2d& origin, double ta, double occluded,
                                     double* signal) {
  // Over the occluder: what the central ray would meet behind its first opaque surface returns
  // attenuated (taller structures behind nearer ones), up to two layers deep.
  const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
  double start = occluded, gain = over_ * ray_gain_[j];
  for (int layer = 0; layer < 2 && start < max_range_ - 0.5 && gain > 1e-12; ++layer) {
    world_.cast(origin + (start + 0.3) * d, angle, ta, max_range_ - start - 0.3, movers_, behind_);
    double pass = 1.0;
    for (const Hit& h : behind_) {
      const double r = start + 0.3 + h.range;
      addReturn(signal, r, h.depth * o_.depth_scale, gain * pass * hitPower(h, r));
      pass *= materialModel(h.material).transmission;
    }
    if (behind_.empty() || materialModel(behind_.back().material).transmission > 0.0) break;
    start += 0.3 + behind_.back().range;
    gain *= over_;
  }
}

void ScanRenderer::addRangeSidelobes(double* signal) {
  // Range sidelobes: two-sided exponential tails, by a forward and a backward recursion.
  if (sidelobe_ > 0) {
    forward_[0] = signal[0];
    for (int b = 1; b < B_; ++b) forward_[b] = signal[b] + side_decay_ * forward_[b - 1];
    backward_[B_ - 1] = signal[B_ - 1];
    for (int b = B_ - 2; b >= 0; --b) backward_[b] = signal[b] + side_decay_ * backward_[b + 1];
    for (int b = 0; b < B_; ++b) signal[b] += sidelobe_ * (forward_[b] + backward_[b] - 2.0 * signal[b]);
  }
  if (pedestal_on_) {
    // The same recursion with the long decay: radial streaks behind (and before) the strongest
    // returns.
    forward_[0] = signal[0];
    for (int b = 1; b < B_; ++b) forward_[b] = signal[b] + pedestal_decay_ * forward_[b - 1];
    backward_[B_ - 1] = signal[B_ - 1];
    for (int b = B_ - 2; b >= 0; --b) backward_[b] = signal[b] + pedestal_decay_ * backward_[b + 1];
    for (int b = 0; b < B_; ++b) signal[b] += pedestal_ * (forward_[b] + backward_[b] - signal[b]);
  }
}

void ScanRenderer::addScatterers() {
  if (!(o_.scatterer_density > 0)) return;
  std::vector<Scatterer> field;
  const double reach = max_range_ + 2.0;
  const long x0 = static_cast<long>(std::floor((centre_.x() - reach) / 10.0)),
             x1 = static_cast<long>(std::floor((centre_.x() + reach) / 10.0));
  const long y0 = static_cast<long>(std::floor((centre_.y() - reach) / 10.0)),
             y1 = static_cast<long>(std::floor((centre_.y() + reach) / 10.0));
  for (long ix = x0; ix <= x1; ++ix)
    for (long iy = y0; iy <= y1; ++iy)
      cellScatterers(seed_, ix, iy, o_.scatterer_density, o_.scatterer_sigma_db, field);
  const double step = 2.0 * kPi / A_;
  const int spread = std::max(1, static_cast<int>(std::ceil(3.0 * beam_sigma_ / step)));
  for (const Scatterer& sc : field) {
    if ((sc.p - centre_.head<2>()).norm() > reach) continue;
    if (world_.pathDistance(sc.p) < o_.scatterer_clearance) continue;
    splatScatterer(sc, spread);
  }
}

int ScanRenderer::lookingAzimuth(const Eigen::Vector2d& p, Pose2& pose) const {
  // The azimuth looking at p: from the mid-sweep pose, then once more from that azimuth's pose.
  const double step = 2.0 * kPi / A_;
  int a = 0;
  pose = centre_;
  for (int iter = 0; iter < 2; ++iter) {
    const Eigen::Vector2d d = p - pose.head<2>();
    const double sensor = oxford_.convention.toSensorAzimuth(normalizeAngle(std::atan2(d.y(), d.x()) - pose.z()));
    a = static_cast<int>(std::lround(sensor / step)) % A_;
    pose = ego_.at(t_ + a * o_.sweep_period / A_);
  }
  return a;
}

void ScanRenderer::splatScatterer(const Scatterer& sc, int spread) {
  Pose2 pose;
  const int a = lookingAzimuth(sc.p, pose);
  const Eigen::Vector2d d = sc.p - pose.head<2>();
  const double r = d.norm();
  if (r >= max_range_ || r < 0.5) return;
  const double bearing = std::atan2(d.y(), d.x()) - pose.z();
  const double p_db =
      o_.target_snr_db + o_.scatterer_db + sc.db - o_.range_loss_db_per_decade * std::log10(std::max(r, 10.0) / 10.0);
  const double power = dbToLinear(p_db);
  const int b0 = std::max(0, static_cast<int>(std::floor((r - 4.0 * sigma_) / res_ - offset_)));
  const int b1 = std::min(B_ - 1, static_cast<int>(std::ceil((r + 4.0 * sigma_) / res_ - offset_)));
  for (int k = -spread; k <= spread; ++k) {
    const int ak = ((a + k) % A_ + A_) % A_;
    const double off = normalizeAngle(bearing - scan_.angle[ak]);
    const double g =
        power * std::exp(-0.5 * (off / beam_sigma_) * (off / beam_sigma_)) * (r < occluded_at_[ak] ? 1.0 : over_);
    if (g < 1e-3) continue;
    double* signal = &signal_all_[static_cast<std::size_t>(ak) * B_];
    for (int b = b0; b <= b1; ++b) {
      const double x = (b + offset_) * res_ - r;
      signal[b] += g * std::exp(-0.5 * (x / sigma_) * (x / sigma_));
    }
  }
}

void ScanRenderer::addAzimuthSidelobes() {
  if (!(o_.azimuth_sidelobe_db > -199.0)) return;
  const double level = dbToLinear(o_.azimuth_sidelobe_db);
  const double step = 2.0 * kPi / A_, width = o_.azimuth_sidelobe_width_deg * kDeg;
  // Taps out to where the sidelobe falls below −50 dB of the return.
  const int K = std::max(
      1, std::min(A_ / 2 - 1, static_cast<int>(std::ceil(width * std::log(std::max(level, 1e-5) / 1e-5) / step))));
  std::vector<double> w(K + 1, 0.0);
  for (int k = 1; k <= K; ++k) w[k] = level * std::exp(-k * step / width);
  std::vector<double> spread(static_cast<std::size_t>(A_) * B_, 0.0);
  for (int a = 0; a < A_; ++a) {
    const double* src = &signal_all_[static_cast<std::size_t>(a) * B_];
    for (int k = 1; k <= K; ++k) {
      double* left = &spread[static_cast<std::size_t>((a + k) % A_) * B_];
      double* right = &spread[static_cast<std::size_t>((a - k + A_) % A_) * B_];
      for (int b = 0; b < B_; ++b) {
        const double v = w[k] * src[b];
        left[b] += v;
        right[b] += v;
      }
    }
  }
  for (std::size_t i = 0; i < signal_all_.size(); ++i) signal_all_[i] += spread[i];
}

std::uint8_t ScanRenderer::countsByte(Random& rng, double s, double mean, bool saturated) const {
  // Navtech's counts: linear power in counts, tabulated exponentials for the noise and the
  // speckle (Gamma of `speckle_looks` = 2 as the mean of two exponentials), the stored value
  // by table. A signal below 2 % of the noise mean is left to the noise.
  const std::vector<float>& exp_table = exp_table_;
  const double knee_lin = knee_lin_;
  double i = mean * exp_table[rng.next() >> 48];
  if (s >= 0.02 || saturated) {
    const double speckle = o_.speckle_looks == 2.0 ? 0.5 * (exp_table[rng.next() >> 48] + exp_table[rng.next() >> 48])
                                                   : gammaMeanOne(rng, o_.speckle_looks);
    i += s * speckle;
    if (saturated) i += saturation_ * (0.8 + 0.4 * rng.uniform());
  }
  if (i > knee_lin) i = knee_lin * std::pow(i / knee_lin, o_.display_compression);
  return countByte(std::floor(o_.noise_counts * i));
}

std::uint8_t ScanRenderer::logByte(Random& rng, double s, double mean, bool saturated, int b) const {
  double db;
  if (s < 1e-3 && !saturated) {
    db = (mean == noise_lin_[b] ? noise_db_[b] : 10.0 * std::log10(mean)) + exp_db_[rng.next() >> 48];
  } else {
    const double speckled = s * gammaMeanOne(rng, o_.speckle_looks);
    double i = mean * -std::log(1.0 - rng.uniform()) + speckled;
    if (saturated) i += saturation_ * (0.8 + 0.4 * rng.uniform());
    db = 10.0 * std::log10(std::max(i, 1e-12));
  }
  if (o_.display_compression < 1.0 && db > o_.display_knee_db)
    db = o_.display_knee_db + (db - o_.display_knee_db) * o_.display_compression;
  const double v = o_.noise_display_level + db / o_.display_db_range;
  return static_cast<std::uint8_t>(std::lround(std::min(std::max(v, 0.0), 1.0) * 255.0));
}

void ScanRenderer::display(Random& rng) {
  const bool counts = o_.display_counts != 0.0;
  for (int a = 0; a < A_; ++a) {
    const double* signal = &signal_all_[static_cast<std::size_t>(a) * B_];
    const bool saturated = rng.chance(o_.saturation_probability);
    const Eigen::Vector2d& origin = origins_[a];
    const Eigen::Vector2d& dir = directions_[a];
    const double occluded = occluded_at_[a];
    std::uint8_t* row = scan_.row(a);
    for (int b = 0; b < B_; ++b) {
      const double r = (b + offset_) * res_;
      double s = signal[b];
      if (r < leak_range_) s += leakage_ * std::exp(-r / o_.leakage_length);
      // Noise and Rayleigh ground clutter add up to one exponential of their summed mean.
      double mean = noise_lin_[b];
      if (clutter_ > 0 && (r < occluded || over_on_)) {
        const double c = groundClutter(seed_, origin + r * dir, o_.ground_clutter_cover);
        if (c > 0) mean += clutter_ * range_gain_[b] * c * (r < occluded ? 1.0 : over_);
      }
      row[b] = counts ? countsByte(rng, s, mean, saturated) : logByte(rng, s, mean, saturated, b);
    }
  }
}

}  // namespace

void renderScan(const World& world, const SimTrajectory& ego, double t, std::uint64_t seed, std::uint64_t frame,
                const ScanningOptions& o, PolarScan& scan) {
  o.validate();
  ScanRenderer renderer(world, ego, t, seed, o, scan);
  renderer.castSweep();
  renderer.addScatterers();
  renderer.addAzimuthSidelobes();
  Random rng(seed, 0x5ca7000000000000ULL + frame);
  renderer.display(rng);
}

}  // namespace sim
}  // namespace radar_ndt
