// radar_sim, part 2: rendering scanning-radar sweeps and automotive-radar detections, and writing
// them as Oxford Radar RobotCar and nuScenes sequences.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <future>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/nuscenes_writer.h"
#include "radar_ndt/io/oxford_ground_truth.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/sim/radar_sim.h"
#include "sim_random.h"

namespace radar_ndt {
namespace sim {
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = kPi / 180.0;

double dbToLinear(double db) {
  return std::pow(10.0, 0.1 * db);
}

/// Standard normal CDF.
double phi(double x) {
  return 0.5 * std::erfc(-x / std::sqrt(2.0));
}

/// Gamma(shape k, scale 1/k) variate with mean 1 (speckle of k looks), Marsaglia–Tsang.
double gammaMeanOne(Random& rng, double k) {
  if (k <= 0.0) return 1.0;
  const double boost = k < 1.0 ? std::pow(rng.uniform() + 1e-300, 1.0 / k) : 1.0;
  const double kk = k < 1.0 ? k + 1.0 : k;
  const double d = kk - 1.0 / 3.0, c = 1.0 / std::sqrt(9.0 * d);
  for (;;) {
    double x, v;
    do {
      x = rng.normal();
      v = 1.0 + c * x;
    } while (v <= 0.0);
    v = v * v * v;
    const double u = rng.uniform();
    if (u < 1.0 - 0.0331 * x * x * x * x || std::log(u) < 0.5 * x * x + d * (1.0 - v + std::log(v)))
      return boost * d * v / k;
  }
}

/// Whether a surface mirrors (multipath), decided once per surface from the seed.
bool specular(std::uint64_t seed, std::uint32_t id, double probability) {
  std::uint64_t x = seed ^ (0x6a09e667f3bcc909ULL + id * 0x9e3779b97f4a7c15ULL);
  return static_cast<double>(splitmix64(x) >> 11) * 0x1.0p-53 < probability;
}

/// The ground-clutter field at a world point: bilinear between 1 m cells, each cluttered with
/// probability `cover` at an exponentially distributed strength of mean 1 (fixed per seed).
double groundClutter(std::uint64_t seed, const Eigen::Vector2d& q, double cover) {
  const double fx = std::floor(q.x()), fy = std::floor(q.y());
  const double ux = q.x() - fx, uy = q.y() - fy;
  const long ix = static_cast<long>(fx), iy = static_cast<long>(fy);
  auto cell = [&](long x, long y) {
    std::uint64_t h = seed * 0xbf58476d1ce4e5b9ULL ^ (static_cast<std::uint64_t>(x) * 0x9e3779b97f4a7c15ULL) ^
                      (static_cast<std::uint64_t>(y) * 0xc2b2ae3d27d4eb4fULL);
    const std::uint64_t r = splitmix64(h);
    const double a = static_cast<double>(r >> 40) * 0x1.0p-24,
                 b = (static_cast<double>(r & 0xffffff) + 0.5) * 0x1.0p-24;
    return a < cover ? -std::log(b) : 0.0;
  };
  return (1 - ux) * (1 - uy) * cell(ix, iy) + ux * (1 - uy) * cell(ix + 1, iy) + (1 - ux) * uy * cell(ix, iy + 1) +
         ux * uy * cell(ix + 1, iy + 1);
}

/// A point scatterer of the fixed scatterer field.
struct Scatterer {
  Eigen::Vector2d p;
  double db;  ///< strength relative to the field's mean level
};

/// The scatterers of the 10 m cell (ix, iy): a Poisson number of them (mean density · 100 m²),
/// uniform in the cell, normal strengths in dB; fixed per seed.
void cellScatterers(std::uint64_t seed, long ix, long iy, double density, double sigma_db,
                    std::vector<Scatterer>& out) {
  constexpr double kCell = 10.0;
  std::uint64_t h = seed * 0x94d049bb133111ebULL ^ (static_cast<std::uint64_t>(ix) * 0x9e3779b97f4a7c15ULL) ^
                    (static_cast<std::uint64_t>(iy) * 0xc2b2ae3d27d4eb4fULL) ^ 0x5ca77e4ULL;
  auto uniform = [&h] { return (static_cast<double>(splitmix64(h) >> 11) + 0.5) * 0x1.0p-53; };
  // Poisson by inversion (means up to a few tens).
  const double mean = density * kCell * kCell;
  double u = uniform(), p = std::exp(-mean), cum = p;
  int n = 0;
  while (u > cum && n < 1000) {
    ++n;
    p *= mean / n;
    cum += p;
  }
  for (int i = 0; i < n; ++i) {
    Scatterer s;
    s.p = Eigen::Vector2d((static_cast<double>(ix) + uniform()) * kCell, (static_cast<double>(iy) + uniform()) * kCell);
    s.db = sigma_db * std::sqrt(-2.0 * std::log(uniform())) * std::cos(2.0 * kPi * uniform());
    out.push_back(s);
  }
}

bool mirrors(Material m) {
  return m == Material::Building || m == Material::Car || m == Material::Bus || m == Material::Wall;
}

/// 10·log10 of an Exp(1) variate, tabulated on 2^16 quantiles (the noise floor's fast path).
const std::vector<float>& exponentialDbTable() {
  static const std::vector<float> table = [] {
    std::vector<float> t(1 << 16);
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double u = (static_cast<double>(i) + 0.5) / t.size();
      t[i] = static_cast<float>(10.0 * std::log10(-std::log(u)));
    }
    return t;
  }();
  return table;
}

/// Exp(1) variates tabulated on 2^16 quantiles (the counts display's noise and speckle).
const std::vector<float>& exponentialTable() {
  static const std::vector<float> table = [] {
    std::vector<float> t(1 << 16);
    for (std::size_t i = 0; i < t.size(); ++i)
      t[i] = static_cast<float>(-std::log((static_cast<double>(i) + 0.5) / t.size()));
    return t;
  }();
  return table;
}

/// Navtech's stored value of a count n: ⌊20·log10 n + 0.12⌋, 0 below 1, at most 255.
std::uint8_t countByte(double n) {
  static const std::vector<std::uint8_t> table = [] {
    std::vector<std::uint8_t> t(4096, 0);
    for (std::size_t k = 1; k < t.size(); ++k)
      t[k] = static_cast<std::uint8_t>(std::min(255.0, std::floor(20.0 * std::log10(static_cast<double>(k)) + 0.12)));
    return t;
  }();
  if (n < 4096.0) return n >= 1.0 ? table[static_cast<std::size_t>(n)] : 0;
  return static_cast<std::uint8_t>(std::min(255.0, std::floor(20.0 * std::log10(n) + 0.12)));
}

std::string token(std::uint64_t seed, std::uint64_t kind, std::uint64_t index) {
  std::uint64_t x = seed * 0x9e3779b97f4a7c15ULL ^ (kind << 48) ^ index;
  const std::uint64_t a = splitmix64(x), b = splitmix64(x);
  char buf[33];
  std::snprintf(buf, sizeof buf, "%016llx%016llx", static_cast<unsigned long long>(a),
                static_cast<unsigned long long>(b));
  return buf;
}

void progressLine(bool on, const char* what, std::size_t k, std::size_t n) {
  if (!on) return;
  if (k + 1 == n || k % 10 == 0) std::fprintf(stderr, "\r%s %zu/%zu", what, k + 1, n);
  if (k + 1 == n) std::fprintf(stderr, "\n");
}

std::int64_t toMicros(double seconds) {
  return static_cast<std::int64_t>(std::llround(seconds * 1e6));
}

}  // namespace

// ---- sensor profiles --------------------------------------------------------------------------

ScanningProfile parseScanningProfile(const std::string& name) {
  if (name == "oxford") return ScanningProfile::Oxford;
  if (name == "radiate") return ScanningProfile::Radiate;
  throw std::invalid_argument("unknown scanning profile '" + name + "' (oxford or radiate)");
}

const char* toString(ScanningProfile profile) {
  return profile == ScanningProfile::Oxford ? "oxford" : "radiate";
}

void applyProfile(ScanningProfile profile, WorldOptions& w, ScanningOptions& s) {
  // The world and sensor settings a profile owns; the seed, geometry and timing stay.
  const std::uint64_t seed = w.seed;
  w = WorldOptions();
  w.seed = seed;
  const ScanningOptions kept = s;
  s = ScanningOptions();
  s.azimuths = kept.azimuths;
  s.bins = kept.bins;
  s.range_resolution = kept.range_resolution;
  s.range_offset_bins = kept.range_offset_bins;
  s.sweep_period = kept.sweep_period;
  s.encoder_size = kept.encoder_size;
  s.max_range = kept.max_range;
  if (profile == ScanningProfile::Oxford) {
    // The sensor: ScanningOptions' defaults. The world it was calibrated in: a dense city.
    w.road_half_width_min = 3.0;
    w.road_half_width_max = 14.0;
    w.building_probability = 0.8;
    w.parked_car_probability = 0.2;
    w.back_rows = 3.0;
    return;
  }
  // Radiate: the earlier calibration against RADIATE's foggy scans (plain log display), in
  // WorldOptions' default world.
  s.beam_width_deg = 2.0;
  s.range_psf_sigma = 0.12;
  s.range_sidelobe_db = -30.0;
  s.range_sidelobe_length = 1.0;
  s.range_loss_db_per_decade = 10.0;
  s.target_snr_db = 30.0;
  s.noise_rise_db = 3.5;
  s.display_knee_db = 10.0;
  s.display_compression = 1.0;
  s.saturation_probability = 0.002;
  s.leakage_db = 34.0;
  s.ground_clutter_cover = 0.4;
  s.display_counts = 0.0;
  s.azimuth_sidelobe_db = -200.0;
  s.range_pedestal_db = -200.0;
  s.over_occluder_db = -200.0;
  s.scatterer_density = 0.0;
  s.depth_scale = 1.0;
}

// ---- scanning radar ---------------------------------------------------------------------------

void renderScan(const World& world, const SimTrajectory& ego, double t, std::uint64_t seed, std::uint64_t frame,
                const ScanningOptions& o, PolarScan& scan) {
  if (o.azimuths <= 0 || o.bins <= 0 || o.range_resolution <= 0 || o.sweep_period <= 0 || o.beam_rays <= 0)
    throw std::invalid_argument(
        "radar_sim: azimuths, bins, range resolution, sweep period and beam rays must be positive");
  if (!(o.display_compression > 0 && o.display_compression <= 1) || !std::isfinite(o.display_knee_db))
    throw std::invalid_argument("radar_sim: display_compression must be in (0, 1] and display_knee_db finite");
  if (!(o.noise_counts > 0) || !(o.leakage_length > 0) || !(o.azimuth_sidelobe_width_deg > 0) ||
      !(o.range_pedestal_length > 0) || !(o.range_offset_bins >= 0))
    throw std::invalid_argument(
        "radar_sim: noise_counts, leakage_length, azimuth_sidelobe_width_deg and range_pedestal_length must be > 0, "
        "range_offset_bins >= 0");
  Random rng(seed, 0x5ca7000000000000ULL + frame);
  const OxfordPolarOptions oxford;
  const int A = o.azimuths, B = o.bins;
  const double res = o.range_resolution, offset = o.range_offset_bins;
  scan.azimuths = A;
  scan.bins = B;
  scan.range_resolution = res;
  scan.range_offset_bins = offset;
  scan.power.assign(static_cast<std::size_t>(A) * B, 0);
  scan.angle.resize(A);
  scan.stamp_us.resize(A);
  scan.measured.assign(A, 1);
  scan.encoder.resize(A);

  // Beam: sub-rays across ±0.9 beam widths with Gaussian two-way gains (σ = width / 2.355).
  const double beam = o.beam_width_deg * kDeg, beam_sigma = beam / 2.355;
  std::vector<double> ray_offset(o.beam_rays), ray_gain(o.beam_rays);
  double gain_sum = 0.0;
  for (int j = 0; j < o.beam_rays; ++j) {
    ray_offset[j] = o.beam_rays == 1 ? 0.0 : (static_cast<double>(j) / (o.beam_rays - 1) - 0.5) * 1.8 * beam;
    ray_gain[j] = std::exp(-0.5 * std::pow(ray_offset[j] / beam_sigma, 2));
    gain_sum += ray_gain[j];
  }
  for (double& g : ray_gain) g /= gain_sum;

  const double max_range = std::min(o.max_range, (B - 1 + offset) * res);
  const Pose2 centre = ego.at(t + 0.5 * o.sweep_period);
  const std::vector<int> movers = world.activeMovers(centre.head<2>(), max_range + 5.0, t + 0.5 * o.sweep_period);

  const double sigma = std::max(o.range_psf_sigma, 1e-3);
  const double sidelobe = dbToLinear(o.range_sidelobe_db);
  const double side_decay = std::exp(-res / std::max(o.range_sidelobe_length, 1e-3));
  const bool pedestal_on = o.range_pedestal_db > -199.0;
  const double pedestal = pedestal_on ? dbToLinear(o.range_pedestal_db) : 0.0;
  const double pedestal_decay = std::exp(-res / o.range_pedestal_length);
  const bool over_on = o.over_occluder_db > -199.0;
  const double over = over_on ? dbToLinear(o.over_occluder_db) : 0.0;
  const double leakage = dbToLinear(o.leakage_db), saturation = dbToLinear(o.saturation_db);
  const double leak_range = 6.0 * o.leakage_length;  // beyond it the leakage is below 1e-2.6 of its peak: not added
  const auto& exp_db = exponentialDbTable();
  std::vector<double> forward(B), backward(B);
  std::vector<float> noise_db(B);
  std::vector<double> noise_lin(B), range_gain(B);
  const double clutter = o.ground_clutter_cover > 0 ? dbToLinear(o.ground_clutter_db) : 0.0;
  for (int b = 0; b < B; ++b) {
    const double r = (b + offset) * res;
    noise_db[b] = static_cast<float>(o.noise_rise_db * std::min(r / max_range, 1.0));
    noise_lin[b] = dbToLinear(noise_db[b]);
    range_gain[b] = dbToLinear(-o.range_loss_db_per_decade * std::log10(std::max(r, 10.0) / 10.0));
  }
  std::vector<Hit> hits, bounce, behind;

  // Pass 1, per azimuth: the received signal (linear power over the noise mean at 0 m) from ray
  // casting, with the range response; where the central ray is stopped and where it leaves the road.
  std::vector<double> signal_all(static_cast<std::size_t>(A) * B, 0.0);
  std::vector<double> occluded_at(A);
  std::vector<Eigen::Vector2d> origins(A), directions(A);
  for (int a = 0; a < A; ++a) {
    scan.encoder[a] =
        static_cast<std::uint16_t>((static_cast<long>(a) * oxford.encoder_size / A) % oxford.encoder_size);
    scan.angle[a] = oxford.convention.toVehicleAngle(2.0 * kPi * scan.encoder[a] / oxford.encoder_size);
    const double ta = t + a * o.sweep_period / A;
    scan.stamp_us[a] = toMicros(ta);  // re-based by the caller
    const Pose2 pose = ego.at(ta);
    const Eigen::Vector2d origin = pose.head<2>();
    double* signal = &signal_all[static_cast<std::size_t>(a) * B];
    double occluded = max_range;  // the central ray's first opaque surface (ground clutter stops there)

    // Adds a return of linear power `p` spread over [r, r + depth] and blurred by the range PSF.
    auto addReturn = [&](double r, double depth, double p) {
      const double lo = r - 4.0 * sigma, hi = r + depth + 4.0 * sigma;
      const int b0 = std::max(0, static_cast<int>(std::floor(lo / res - offset)));
      const int b1 = std::min(B - 1, static_cast<int>(std::ceil(hi / res - offset)));
      const double norm = sigma * std::sqrt(2.0 * kPi) / std::max(depth, 1e-3);
      for (int b = b0; b <= b1; ++b) {
        const double x = (b + offset) * res - r;
        const double k = depth > 1e-3 ? (phi(x / sigma) - phi((x - depth) / sigma)) * norm
                                      : std::exp(-0.5 * (x / sigma) * (x / sigma));
        signal[b] += p * k;
      }
    };
    // Power (linear, over the noise mean) of a hit at range r, before the beam gain.
    auto hitPower = [&](const Hit& h, double r) {
      const MaterialModel& m = materialModel(h.material);
      double db = o.target_snr_db + m.reflect_db - o.range_loss_db_per_decade * std::log10(std::max(r, 10.0) / 10.0);
      if (m.incidence_exp > 0) db += 10.0 * m.incidence_exp * std::log10(std::max(h.cos_incidence, 0.03));
      return dbToLinear(db);
    };

    for (int j = 0; j < o.beam_rays; ++j) {
      const double angle = pose.z() + scan.angle[a] + ray_offset[j];
      world.cast(origin, angle, ta, max_range, movers, hits);
      double through = 1.0;  // share of the power left after transmissive hits
      const bool central = j == o.beam_rays / 2;
      if (central && !hits.empty() && materialModel(hits.back().material).transmission <= 0.0)
        occluded = hits.back().range;
      for (const Hit& h : hits) {
        addReturn(h.range, h.depth * o.depth_scale, ray_gain[j] * through * hitPower(h, h.range));
        through *= materialModel(h.material).transmission;
      }
      // Multipath: the central ray bounces off a mirroring surface; what it meets next shows up
      // behind the mirror at the total path length.
      if (central && !hits.empty() && o.ghost_probability > 0) {
        const Hit& h = hits.back();
        if (mirrors(h.material) && h.cos_incidence > 0.25 && specular(seed, h.id, o.ghost_probability)) {
          const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
          const Eigen::Vector2d m = d - 2.0 * d.dot(h.normal) * h.normal;
          const Eigen::Vector2d p = origin + h.range * d + 0.05 * m;
          world.cast(p, std::atan2(m.y(), m.x()), ta, max_range - h.range, movers, bounce);
          if (!bounce.empty()) {
            const Hit& g = bounce.back();
            const double r = h.range + g.range;
            if (r < max_range)
              addReturn(r, g.depth * o.depth_scale, hitPower(g, r) * dbToLinear(-o.ghost_attenuation_db));
          }
        }
      }
      // Over the occluder: what the central ray would meet behind its first opaque surface returns
      // attenuated (taller structures behind nearer ones), up to two layers deep.
      if (central && over_on && occluded < max_range) {
        const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
        double start = occluded, gain = over * ray_gain[j];
        for (int layer = 0; layer < 2 && start < max_range - 0.5 && gain > 1e-12; ++layer) {
          world.cast(origin + (start + 0.3) * d, angle, ta, max_range - start - 0.3, movers, behind);
          double pass = 1.0;
          for (const Hit& h : behind) {
            const double r = start + 0.3 + h.range;
            addReturn(r, h.depth * o.depth_scale, gain * pass * hitPower(h, r));
            pass *= materialModel(h.material).transmission;
          }
          if (behind.empty() || materialModel(behind.back().material).transmission > 0.0) break;
          start += 0.3 + behind.back().range;
          gain *= over;
        }
      }
    }

    // Range sidelobes: two-sided exponential tails, by a forward and a backward recursion.
    if (sidelobe > 0) {
      forward[0] = signal[0];
      for (int b = 1; b < B; ++b) forward[b] = signal[b] + side_decay * forward[b - 1];
      backward[B - 1] = signal[B - 1];
      for (int b = B - 2; b >= 0; --b) backward[b] = signal[b] + side_decay * backward[b + 1];
      for (int b = 0; b < B; ++b) signal[b] += sidelobe * (forward[b] + backward[b] - 2.0 * signal[b]);
    }
    if (pedestal_on) {
      // The same recursion with the long decay: radial streaks behind (and before) the strongest
      // returns.
      forward[0] = signal[0];
      for (int b = 1; b < B; ++b) forward[b] = signal[b] + pedestal_decay * forward[b - 1];
      backward[B - 1] = signal[B - 1];
      for (int b = B - 2; b >= 0; --b) backward[b] = signal[b] + pedestal_decay * backward[b + 1];
      for (int b = 0; b < B; ++b) signal[b] += pedestal * (forward[b] + backward[b] - signal[b]);
    }
    occluded_at[a] = occluded;
    origins[a] = origin;
    const double beam_angle = pose.z() + scan.angle[a];
    directions[a] = Eigen::Vector2d(std::cos(beam_angle), std::sin(beam_angle));
  }

  // Pass 1b: the scatterer field, splatted through the beam's main lobe (Gaussian in azimuth) and
  // the range response; each is seen from the pose of the azimuth that looks at it (motion
  // distortion), attenuated behind that azimuth's first opaque surface.
  if (o.scatterer_density > 0) {
    std::vector<Scatterer> field;
    const double reach = max_range + 2.0;
    const long x0 = static_cast<long>(std::floor((centre.x() - reach) / 10.0)),
               x1 = static_cast<long>(std::floor((centre.x() + reach) / 10.0));
    const long y0 = static_cast<long>(std::floor((centre.y() - reach) / 10.0)),
               y1 = static_cast<long>(std::floor((centre.y() + reach) / 10.0));
    for (long ix = x0; ix <= x1; ++ix)
      for (long iy = y0; iy <= y1; ++iy) cellScatterers(seed, ix, iy, o.scatterer_density, o.scatterer_sigma_db, field);
    const double step = 2.0 * kPi / A;
    const int spread = std::max(1, static_cast<int>(std::ceil(3.0 * beam_sigma / step)));
    for (const Scatterer& sc : field) {
      if ((sc.p - centre.head<2>()).norm() > reach) continue;
      if (world.pathDistance(sc.p) < o.scatterer_clearance) continue;
      // The azimuth looking at it: from the mid-sweep pose, then once more from that azimuth's pose.
      int a = 0;
      Pose2 pose = centre;
      for (int iter = 0; iter < 2; ++iter) {
        const Eigen::Vector2d d = sc.p - pose.head<2>();
        const double sensor = oxford.convention.toSensorAzimuth(normalizeAngle(std::atan2(d.y(), d.x()) - pose.z()));
        a = static_cast<int>(std::lround(sensor / step)) % A;
        pose = ego.at(t + a * o.sweep_period / A);
      }
      const Eigen::Vector2d d = sc.p - pose.head<2>();
      const double r = d.norm();
      if (r >= max_range || r < 0.5) continue;
      const double bearing = std::atan2(d.y(), d.x()) - pose.z();
      const double p_db =
          o.target_snr_db + o.scatterer_db + sc.db - o.range_loss_db_per_decade * std::log10(std::max(r, 10.0) / 10.0);
      const double power = dbToLinear(p_db);
      const int b0 = std::max(0, static_cast<int>(std::floor((r - 4.0 * sigma) / res - offset)));
      const int b1 = std::min(B - 1, static_cast<int>(std::ceil((r + 4.0 * sigma) / res - offset)));
      for (int k = -spread; k <= spread; ++k) {
        const int ak = ((a + k) % A + A) % A;
        const double off = normalizeAngle(bearing - scan.angle[ak]);
        const double g =
            power * std::exp(-0.5 * (off / beam_sigma) * (off / beam_sigma)) * (r < occluded_at[ak] ? 1.0 : over);
        if (g < 1e-3) continue;
        double* signal = &signal_all[static_cast<std::size_t>(ak) * B];
        for (int b = b0; b <= b1; ++b) {
          const double x = (b + offset) * res - r;
          signal[b] += g * std::exp(-0.5 * (x / sigma) * (x / sigma));
        }
      }
    }
  }

  // Pass 2: antenna sidelobes in azimuth (circular over the sweep).
  if (o.azimuth_sidelobe_db > -199.0) {
    const double level = dbToLinear(o.azimuth_sidelobe_db);
    const double step = 2.0 * kPi / A, width = o.azimuth_sidelobe_width_deg * kDeg;
    // Taps out to where the sidelobe falls below −50 dB of the return.
    const int K = std::max(
        1, std::min(A / 2 - 1, static_cast<int>(std::ceil(width * std::log(std::max(level, 1e-5) / 1e-5) / step))));
    std::vector<double> w(K + 1, 0.0);
    for (int k = 1; k <= K; ++k) w[k] = level * std::exp(-k * step / width);
    std::vector<double> spread(static_cast<std::size_t>(A) * B, 0.0);
    for (int a = 0; a < A; ++a) {
      const double* src = &signal_all[static_cast<std::size_t>(a) * B];
      for (int k = 1; k <= K; ++k) {
        double* left = &spread[static_cast<std::size_t>((a + k) % A) * B];
        double* right = &spread[static_cast<std::size_t>((a - k + A) % A) * B];
        for (int b = 0; b < B; ++b) {
          const double v = w[k] * src[b];
          left[b] += v;
          right[b] += v;
        }
      }
    }
    for (std::size_t i = 0; i < signal_all.size(); ++i) signal_all[i] += spread[i];
  }

  // Pass 3, per azimuth: leakage, noise, ground clutter, speckle and the display.
  const bool counts = o.display_counts != 0.0;
  const double count_scale = o.noise_counts;
  const auto& exp_table = exponentialTable();
  const double knee_lin =
      o.display_compression < 1.0 ? dbToLinear(o.display_knee_db) : std::numeric_limits<double>::infinity();
  for (int a = 0; a < A; ++a) {
    const double* signal = &signal_all[static_cast<std::size_t>(a) * B];
    const bool saturated = rng.chance(o.saturation_probability);
    const Eigen::Vector2d& origin = origins[a];
    const Eigen::Vector2d& dir = directions[a];
    const double occluded = occluded_at[a];
    std::uint8_t* row = scan.row(a);
    for (int b = 0; b < B; ++b) {
      const double r = (b + offset) * res;
      double s = signal[b];
      if (r < leak_range) s += leakage * std::exp(-r / o.leakage_length);
      // Noise and Rayleigh ground clutter add up to one exponential of their summed mean.
      double mean = noise_lin[b];
      if (clutter > 0 && (r < occluded || over_on)) {
        const double c = groundClutter(seed, origin + r * dir, o.ground_clutter_cover);
        if (c > 0) mean += clutter * range_gain[b] * c * (r < occluded ? 1.0 : over);
      }
      if (counts) {
        // Navtech's counts: linear power in counts, tabulated exponentials for the noise and the
        // speckle (Gamma of `speckle_looks` = 2 as the mean of two exponentials), the stored value
        // by table. A signal below 2 % of the noise mean is left to the noise.
        double i = mean * exp_table[rng.next() >> 48];
        if (s >= 0.02 || saturated) {
          const double speckle = o.speckle_looks == 2.0
                                     ? 0.5 * (exp_table[rng.next() >> 48] + exp_table[rng.next() >> 48])
                                     : gammaMeanOne(rng, o.speckle_looks);
          i += s * speckle;
          if (saturated) i += saturation * (0.8 + 0.4 * rng.uniform());
        }
        if (i > knee_lin) i = knee_lin * std::pow(i / knee_lin, o.display_compression);
        row[b] = countByte(std::floor(count_scale * i));
        continue;
      }
      double db;
      if (s < 1e-3 && !saturated) {
        db = (mean == noise_lin[b] ? noise_db[b] : 10.0 * std::log10(mean)) + exp_db[rng.next() >> 48];
      } else {
        const double speckled = s * gammaMeanOne(rng, o.speckle_looks);
        double i = mean * -std::log(1.0 - rng.uniform()) + speckled;
        if (saturated) i += saturation * (0.8 + 0.4 * rng.uniform());
        db = 10.0 * std::log10(std::max(i, 1e-12));
      }
      if (o.display_compression < 1.0 && db > o.display_knee_db)
        db = o.display_knee_db + (db - o.display_knee_db) * o.display_compression;
      const double v = o.noise_display_level + db / o.display_db_range;
      row[b] = static_cast<std::uint8_t>(std::lround(std::min(std::max(v, 0.0), 1.0) * 255.0));
    }
  }
}

SequenceSummary writeScanningSequence(const std::string& dir, const SimTrajectory& ego,
                                      const WorldOptions& world_options, const ScanningOptions& options,
                                      const SequenceOptions& sequence) {
  const auto wall = std::chrono::steady_clock::now();
  if (sequence.start >= ego.size()) throw std::invalid_argument("radar_sim: --start is past the trajectory's end");
  const std::size_t available = ego.size() - sequence.start;
  const std::size_t frames = sequence.frames == 0 ? available : std::min(sequence.frames, available);
  if (frames < 2) throw std::invalid_argument("radar_sim: a sequence needs at least 2 frames");
  std::error_code ec;
  fs::create_directories(fs::path(dir) / "radar", ec);
  fs::create_directories(fs::path(dir) / "gt", ec);
  if (ec) throw IoError(dir, "cannot create the output directories: " + ec.message());

  const World world = World::generate(ego, world_options);
  const double t0 = ego.stamps()[sequence.start];
  std::vector<OxfordStamp> stamps;
  std::vector<OxfordRelativePose> rows;
  std::ostringstream poses;
  poses << std::setprecision(9);
  // Two buffers: scan k is encoded and written on a second thread while scan k+1 is rendered.
  PolarScan buffers[2];
  std::future<void> writing;
  const OxfordPolarOptions oxford;
  Pose2 first = Pose2::Zero(), previous = Pose2::Zero();
  std::int64_t previous_stamp = 0;
  for (std::size_t k = 0; k < frames; ++k) {
    const double t = ego.stamps()[sequence.start + k];
    PolarScan& scan = buffers[k % 2];
    renderScan(world, ego, t, world_options.seed, k, options, scan);
    const std::int64_t stamp = sequence.start_stamp_us + toMicros(t - t0);
    const std::int64_t base = toMicros(t);
    for (auto& s : scan.stamp_us) s = stamp + (s - base);
    scan.stamp = stamp;
    if (writing.valid()) writing.get();  // rethrows a failed write
    writing = std::async(
        std::launch::async,
        [&scan, &oxford, &sequence, path = (fs::path(dir) / "radar" / (std::to_string(stamp) + ".png")).string()] {
          writeOxfordPolarPng(path, scan, oxford, sequence.png_compression);
        });
    stamps.push_back({stamp, true});
    const Pose2 pose = ego.at(t);
    if (k == 0) first = pose;
    const Pose2 rel = between(first, pose);
    const double c = std::cos(rel.z()), s = std::sin(rel.z());
    poses << c << ' ' << -s << " 0 " << rel.x() << ' ' << s << ' ' << c << " 0 " << rel.y() << " 0 0 1 0\n";
    if (k > 0) {
      const Pose2 d = between(previous, pose);  // the later scan in the earlier one's frame
      // As the dataset writes them: source/destination_timestamp half a sweep after the scans'
      // radar timestamps (its poses are mid-sweep), the radar timestamps in their own columns.
      const std::int64_t half_sweep = toMicros(0.5 * options.sweep_period);
      OxfordRelativePose row;
      row.source = stamp + half_sweep;
      row.destination = previous_stamp + half_sweep;
      row.x = d.x();
      row.y = -d.y();  // Oxford axes: y right, z down
      row.yaw = -d.z();
      row.source_radar = stamp;
      row.destination_radar = previous_stamp;
      rows.push_back(row);
    }
    previous = pose;
    previous_stamp = stamp;
    progressLine(sequence.progress, "radar_sim: scan", k, frames);
  }
  if (writing.valid()) writing.get();
  writeOxfordTimestamps((fs::path(dir) / "radar.timestamps").string(), stamps);
  writeOxfordRadarOdometry((fs::path(dir) / "gt" / "radar_odometry.csv").string(), rows);
  writeFileAtomically((fs::path(dir) / "gt" / "poses.txt").string(), poses.str());

  SequenceSummary summary;
  summary.frames = frames;
  summary.duration = ego.stamps()[sequence.start + frames - 1] - t0;
  summary.distance = ego.arcAt(t0 + summary.duration) - ego.arcAt(t0);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
  return summary;
}

// ---- automotive radar -------------------------------------------------------------------------

namespace {

struct Mounting {
  const char* channel;
  double x, y, z, yaw_deg;
};
// nuScenes' five ARS408 mountings (calibrated_sensor of the nuScenes vehicles).
constexpr std::array<Mounting, 5> kMountings{{{"RADAR_FRONT", 3.412, 0.0, 0.5, 0.2},
                                              {"RADAR_FRONT_LEFT", 2.422, 0.8, 0.78, 88.36},
                                              {"RADAR_FRONT_RIGHT", 2.422, -0.8, 0.77, -90.98},
                                              {"RADAR_BACK_LEFT", -0.562, 0.628, 0.53, 174.41},
                                              {"RADAR_BACK_RIGHT", -0.562, -0.618, 0.53, -176.11}}};

struct Detection {
  double x, y;  // sensor frame
  double vr;    // radial velocity, positive receding
  double rcs;
  bool moving;
  double sx, sy;    // position standard deviations in the sensor frame
  double vr_world;  // the target's own radial velocity (for vx_comp / vy_comp)
};

/// Detections as the nuScenes radar PCD stores them (sensor frame, ARS408 state indices).
std::vector<NuScenesRadarPoint> toPcdPoints(const std::vector<Detection>& dets, double doppler_sigma) {
  std::vector<NuScenesRadarPoint> points(dets.size());
  const std::int8_t v_rms = static_cast<std::int8_t>(ars408RmsIndex(doppler_sigma));
  for (std::size_t i = 0; i < dets.size(); ++i) {
    const Detection& d = dets[i];
    const double r = std::max(std::hypot(d.x, d.y), 1e-6), ux = d.x / r, uy = d.y / r;
    NuScenesRadarPoint& p = points[i];
    p.x = static_cast<float>(d.x);
    p.y = static_cast<float>(d.y);
    p.z = 0.f;
    p.dyn_prop = d.moving ? 0 : 1;  // 0 moving, 1 stationary
    p.id = static_cast<std::int16_t>(i);
    p.rcs = static_cast<float>(d.rcs);
    p.vx = static_cast<float>(d.vr * ux);
    p.vy = static_cast<float>(d.vr * uy);
    p.vx_comp = static_cast<float>(d.vr_world * ux);
    p.vy_comp = static_cast<float>(d.vr_world * uy);
    p.is_quality_valid = 1;
    p.ambig_state = 3;  // unambiguous
    p.x_rms = static_cast<std::int8_t>(ars408RmsIndex(d.sx));
    p.y_rms = static_cast<std::int8_t>(ars408RmsIndex(d.sy));
    p.invalid_state = 0;  // valid
    p.pdh0 = 1;           // false-alarm probability < 25 %
    p.vx_rms = v_rms;
    p.vy_rms = v_rms;
  }
  return points;
}

/// nuScenes' (w, x, y, z) of a rotation about z.
std::array<double, 4> quaternionYaw(double yaw) {
  return {std::cos(0.5 * yaw), 0.0, 0.0, std::sin(0.5 * yaw)};
}

}  // namespace

SequenceSummary writeAutomotiveSequence(const std::string& dir, const SimTrajectory& ego,
                                        const WorldOptions& world_options, const AutomotiveOptions& o,
                                        const SequenceOptions& sequence) {
  const auto wall = std::chrono::steady_clock::now();
  if (sequence.start >= ego.size()) throw std::invalid_argument("radar_sim: --start is past the trajectory's end");
  if (!(o.period > 0)) throw std::invalid_argument("radar_sim: the radar period must be positive");
  const double t0 = ego.stamps()[sequence.start];
  const double available = ego.endTime() - t0 - o.period - 2.0 * o.jitter;
  const std::size_t max_frames = available > 0 ? static_cast<std::size_t>(available / o.period) : 0;
  const std::size_t frames = sequence.frames == 0 ? max_frames : std::min(sequence.frames, max_frames);
  if (frames < 2) throw std::invalid_argument("radar_sim: the trajectory is too short for 2 radar cycles");
  const double duration = frames * o.period;
  const std::string table_dir = (fs::path(dir) / "v1.0-sim").string();
  std::error_code ec;
  fs::create_directories(table_dir, ec);
  for (const auto& m : kMountings) {
    fs::create_directories(fs::path(dir) / "samples" / m.channel, ec);
    fs::create_directories(fs::path(dir) / "sweeps" / m.channel, ec);
  }
  if (ec) throw IoError(dir, "cannot create the output directories: " + ec.message());

  const World world = World::generate(ego, world_options);
  const std::uint64_t seed = world_options.seed;
  Random phase_rng(seed, 0xa070000000000000ULL);

  NuScenesTableWriter tables;
  const std::string log_token = token(seed, 1, 0), scene_token = token(seed, 2, 0);
  // Samples (key frames) every 0.5 s, as in nuScenes.
  const std::size_t nsamples = static_cast<std::size_t>(duration / 0.5) + 1;
  auto stampOf = [&](double t) { return sequence.start_stamp_us + toMicros(t - t0); };
  for (std::size_t i = 0; i < nsamples; ++i)
    tables.addSample(token(seed, 3, i), stampOf(t0 + 0.5 * i), i ? token(seed, 3, i - 1) : "",
                     i + 1 < nsamples ? token(seed, 3, i + 1) : "", scene_token);

  std::vector<Hit> hits;
  std::size_t total_detections = 0, data_index = 0;
  for (std::size_t c = 0; c < kMountings.size(); ++c) {
    const Mounting& mount = kMountings[c];
    const std::string sensor_token = token(seed, 4, c), calib_token = token(seed, 5, c);
    tables.addSensor(sensor_token, mount.channel, "radar");
    tables.addCalibratedSensor(calib_token, sensor_token, {mount.x, mount.y, mount.z},
                               quaternionYaw(mount.yaw_deg * kDeg));
    const Pose2 mount_pose(mount.x, mount.y, mount.yaw_deg * kDeg);
    // Unsynchronised radars: each its own phase; the front one starts the cycle clock.
    const double phase = c == 0 ? 0.0 : phase_rng.uniform(0.0, o.period);
    const std::size_t sweeps = c == 0 ? frames : static_cast<std::size_t>((duration - phase) / o.period);
    std::vector<double> times(sweeps);
    Random jitter_rng(seed, 0xa071000000000000ULL + c);
    for (std::size_t k = 0; k < sweeps; ++k)
      times[k] = t0 + o.jitter + phase + k * o.period + jitter_rng.uniform(-o.jitter, o.jitter);
    // Key frame: the sweep of this channel nearest each sample time.
    std::vector<std::size_t> sample_of(sweeps);
    std::vector<bool> key(sweeps, false);
    for (std::size_t k = 0; k < sweeps; ++k)
      sample_of[k] = std::min<std::size_t>(nsamples - 1, static_cast<std::size_t>(std::lround((times[k] - t0) / 0.5)));
    for (std::size_t i = 0; i < nsamples; ++i) {
      std::size_t best = sweeps;
      for (std::size_t k = 0; k < sweeps; ++k)
        if (best == sweeps || std::abs(times[k] - (t0 + 0.5 * i)) < std::abs(times[best] - (t0 + 0.5 * i))) best = k;
      if (best < sweeps && std::abs(times[best] - (t0 + 0.5 * i)) < 0.5 * o.period) key[best] = true;
    }

    for (std::size_t k = 0; k < sweeps; ++k) {
      const double t = times[k];
      Random rng(seed, 0xa072000000000000ULL + (static_cast<std::uint64_t>(c) << 32) + k);
      const Pose2 pose = ego.at(t);
      const Pose2 sensor = compose(pose, mount_pose);
      const Eigen::Vector3d vel = ego.velocity(t);  // body (vx, vy, ω)
      // Sensor velocity in the world: v + ω × r, rotated by the vehicle heading.
      const Eigen::Vector2d v_body(vel.x() - vel.z() * mount.y, vel.y() + vel.z() * mount.x);
      const double ch = std::cos(pose.z()), sh = std::sin(pose.z());
      const Eigen::Vector2d v_sensor(ch * v_body.x() - sh * v_body.y(), sh * v_body.x() + ch * v_body.y());
      const std::vector<int> movers = world.activeMovers(sensor.head<2>(), o.far_range + 5.0, t);

      std::vector<Detection> raw;
      const double fov = std::max(o.near_fov_deg, o.far_fov_deg);
      for (double az = -fov; az <= fov + 1e-9; az += o.ray_step_deg) {
        const double reach = std::abs(az) <= o.far_fov_deg ? o.far_range : o.near_range;
        const double phi_s = az * kDeg;
        world.cast(sensor.head<2>(), sensor.z() + phi_s, t, reach, movers, hits);
        double through = 1.0;
        for (const Hit& h : hits) {
          const MaterialModel& m = materialModel(h.material);
          const double p =
              std::min(0.95, o.detection_probability * through * std::clamp(0.5 + m.rcs_dbsm / 20.0, 0.2, 1.5));
          through *= m.transmission;
          if (!rng.chance(p)) continue;
          const Eigen::Vector2d u(std::cos(sensor.z() + phi_s), std::sin(sensor.z() + phi_s));
          const double vr_target = h.velocity.dot(u);
          const double vr = vr_target - v_sensor.dot(u);
          const bool far_mode = std::abs(az) <= o.far_fov_deg && h.range > o.near_range;
          const double sr = far_mode ? 2.0 * o.range_sigma : o.range_sigma;
          const double sa = (far_mode ? 0.5 : 1.0) * o.azimuth_sigma_deg * kDeg * (1.0 + std::abs(az) / 60.0);
          const double r = h.range + sr * rng.normal(), a = phi_s + sa * rng.normal();
          Detection d;
          d.x = r * std::cos(a);
          d.y = r * std::sin(a);
          d.vr = vr + o.doppler_sigma * rng.normal();
          d.vr_world = vr_target;
          d.rcs = m.rcs_dbsm + o.rcs_sigma_db * rng.normal();
          d.moving = h.velocity.norm() > 0.5;
          // Position standard deviations in the sensor frame, from the polar ones.
          d.sx = std::hypot(sr * std::cos(a), r * sa * std::sin(a));
          d.sy = std::hypot(sr * std::sin(a), r * sa * std::cos(a));
          raw.push_back(d);
          // Multipath off a moving vehicle: a ghost at twice the range, with twice the Doppler.
          if ((h.material == Material::Car || h.material == Material::Bus) && rng.chance(o.ghost_probability)) {
            Detection g = d;
            g.x *= 1.8;
            g.y *= 1.8;
            g.vr *= 2.0;
            g.rcs -= 8.0;
            raw.push_back(g);
          }
        }
      }
      // Clutter: false detections anywhere in the near field of view.
      const int clutter = rng.poisson(o.clutter_per_sweep);
      for (int i = 0; i < clutter; ++i) {
        const double r = rng.uniform(1.0, o.near_range), a = rng.uniform(-o.near_fov_deg, o.near_fov_deg) * kDeg;
        Detection d{r * std::cos(a),
                    r * std::sin(a),
                    rng.uniform(-6.0, 6.0),
                    rng.uniform(-10.0, 5.0),
                    true,
                    o.range_sigma,
                    r * o.azimuth_sigma_deg * kDeg,
                    0.0};
        raw.push_back(d);
      }
      // Returns closer than the cluster distance merge into one detection (the strongest).
      std::sort(raw.begin(), raw.end(), [](const Detection& a, const Detection& b) { return a.rcs > b.rcs; });
      std::vector<Detection> dets;
      for (const Detection& d : raw) {
        bool merged = false;
        for (const Detection& e : dets)
          if (std::hypot(d.x - e.x, d.y - e.y) < o.cluster_distance) {
            merged = true;
            break;
          }
        if (!merged) dets.push_back(d);
        if (static_cast<int>(dets.size()) >= o.max_detections) break;
      }
      std::sort(dets.begin(), dets.end(),
                [](const Detection& a, const Detection& b) { return std::hypot(a.x, a.y) < std::hypot(b.x, b.y); });
      total_detections += dets.size();

      const std::int64_t stamp = stampOf(t);
      const std::string folder = key[k] ? "samples" : "sweeps";
      const std::string filename = folder + "/" + mount.channel + "/" + sequence.scene_name + "__" + mount.channel +
                                   "__" + std::to_string(stamp) + ".pcd";
      writeNuScenesRadarPcd((fs::path(dir) / filename).string(), toPcdPoints(dets, o.doppler_sigma));
      const std::string ego_token = token(seed, 6, data_index);
      tables.addEgoPose(ego_token, stamp, quaternionYaw(pose.z()), {pose.x(), pose.y(), 0.0});
      tables.addSampleData(token(seed, 7, data_index), token(seed, 3, sample_of[k]), ego_token, calib_token, stamp,
                           static_cast<bool>(key[k]), filename, k ? token(seed, 7, data_index - 1) : "",
                           k + 1 < sweeps ? token(seed, 7, data_index + 1) : "");
      ++data_index;
      if (c == 0) progressLine(sequence.progress, "radar_sim: front sweep", k, sweeps);
    }
  }
  tables.addLog(log_token, "radar_sim-seed-" + std::to_string(seed), "radar_sim", "", "simulated");
  tables.addScene(scene_token, log_token, nsamples, token(seed, 3, 0), token(seed, 3, nsamples - 1),
                  sequence.scene_name,
                  "radar_sim automotive sequence, seed " + std::to_string(seed) + ", " +
                      std::to_string(total_detections) + " detections");
  tables.write(table_dir);

  SequenceSummary summary;
  summary.frames = frames;
  summary.duration = duration;
  summary.distance = ego.arcAt(t0 + duration) - ego.arcAt(t0);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
  return summary;
}

}  // namespace sim
}  // namespace radar_ndt
