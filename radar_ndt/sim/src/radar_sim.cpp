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
#include <sstream>
#include <stdexcept>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/nuscenes_writer.h"
#include "radar_ndt/sim/radar_sim.h"
#include "sim_random.h"

namespace radar_ndt {
namespace sim {
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = kPi / 180.0;

double dbToLinear(double db) { return std::pow(10.0, 0.1 * db); }

/// Standard normal CDF.
double phi(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

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
    const double a = static_cast<double>(r >> 40) * 0x1.0p-24, b = (static_cast<double>(r & 0xffffff) + 0.5) * 0x1.0p-24;
    return a < cover ? -std::log(b) : 0.0;
  };
  return (1 - ux) * (1 - uy) * cell(ix, iy) + ux * (1 - uy) * cell(ix + 1, iy) + (1 - ux) * uy * cell(ix, iy + 1) +
         ux * uy * cell(ix + 1, iy + 1);
}

bool mirrors(Material m) { return m == Material::Building || m == Material::Car || m == Material::Bus || m == Material::Wall; }

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

std::string token(std::uint64_t seed, std::uint64_t kind, std::uint64_t index) {
  std::uint64_t x = seed * 0x9e3779b97f4a7c15ULL ^ (kind << 48) ^ index;
  const std::uint64_t a = splitmix64(x), b = splitmix64(x);
  char buf[33];
  std::snprintf(buf, sizeof buf, "%016llx%016llx", static_cast<unsigned long long>(a), static_cast<unsigned long long>(b));
  return buf;
}

void progressLine(bool on, const char* what, std::size_t k, std::size_t n) {
  if (!on) return;
  if (k + 1 == n || k % 10 == 0) std::fprintf(stderr, "\r%s %zu/%zu", what, k + 1, n);
  if (k + 1 == n) std::fprintf(stderr, "\n");
}

std::int64_t toMicros(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e6)); }

}  // namespace

// ---- scanning radar ---------------------------------------------------------------------------

void renderScan(const World& world, const SimTrajectory& ego, double t, std::uint64_t seed, std::uint64_t frame,
                const ScanningOptions& o, PolarScan& scan) {
  if (o.azimuths <= 0 || o.bins <= 0 || o.range_resolution <= 0 || o.sweep_period <= 0 || o.beam_rays <= 0)
    throw std::invalid_argument("radar_sim: azimuths, bins, range resolution, sweep period and beam rays must be positive");
  if (!(o.display_compression > 0 && o.display_compression <= 1) || !std::isfinite(o.display_knee_db))
    throw std::invalid_argument("radar_sim: display_compression must be in (0, 1] and display_knee_db finite");
  Random rng(seed, 0x5ca7000000000000ULL + frame);
  const OxfordPolarOptions oxford;
  const int A = o.azimuths, B = o.bins;
  const double res = o.range_resolution, offset = oxford.convention.range_offset_bins;
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
  const double leakage = dbToLinear(o.leakage_db), saturation = dbToLinear(o.saturation_db);
  const auto& exp_db = exponentialDbTable();
  std::vector<double> signal(B), forward(B), backward(B);
  std::vector<float> noise_db(B);
  std::vector<double> noise_lin(B), range_gain(B);
  const double clutter = o.ground_clutter_cover > 0 ? dbToLinear(o.ground_clutter_db) : 0.0;
  for (int b = 0; b < B; ++b) {
    const double r = (b + offset) * res;
    noise_db[b] = static_cast<float>(o.noise_rise_db * std::min(r / max_range, 1.0));
    noise_lin[b] = dbToLinear(noise_db[b]);
    range_gain[b] = dbToLinear(-o.range_loss_db_per_decade * std::log10(std::max(r, 10.0) / 10.0));
  }
  std::vector<Hit> hits, bounce;

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

  for (int a = 0; a < A; ++a) {
    scan.encoder[a] = static_cast<std::uint16_t>((static_cast<long>(a) * oxford.encoder_size / A) % oxford.encoder_size);
    scan.angle[a] = oxford.convention.toVehicleAngle(2.0 * kPi * scan.encoder[a] / oxford.encoder_size);
    const double ta = t + a * o.sweep_period / A;
    scan.stamp_us[a] = toMicros(ta);  // re-based by the caller
    const Pose2 pose = ego.at(ta);
    const Eigen::Vector2d origin = pose.head<2>();
    std::fill(signal.begin(), signal.end(), 0.0);
    double occluded = max_range;  // the central ray's first opaque surface (ground clutter stops there)

    for (int j = 0; j < o.beam_rays; ++j) {
      const double angle = pose.z() + scan.angle[a] + ray_offset[j];
      world.cast(origin, angle, ta, max_range, movers, hits);
      double through = 1.0;  // share of the power left after transmissive hits
      if (j == o.beam_rays / 2 && !hits.empty() && materialModel(hits.back().material).transmission <= 0.0)
        occluded = hits.back().range;
      for (const Hit& h : hits) {
        addReturn(h.range, h.depth, ray_gain[j] * through * hitPower(h, h.range));
        through *= materialModel(h.material).transmission;
      }
      // Multipath: the central ray bounces off a mirroring surface; what it meets next shows up
      // behind the mirror at the total path length.
      if (j == o.beam_rays / 2 && !hits.empty() && o.ghost_probability > 0) {
        const Hit& h = hits.back();
        if (mirrors(h.material) && h.cos_incidence > 0.25 && specular(seed, h.id, o.ghost_probability)) {
          const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
          const Eigen::Vector2d m = d - 2.0 * d.dot(h.normal) * h.normal;
          const Eigen::Vector2d p = origin + h.range * d + 0.05 * m;
          world.cast(p, std::atan2(m.y(), m.x()), ta, max_range - h.range, movers, bounce);
          if (!bounce.empty()) {
            const Hit& g = bounce.back();
            const double r = h.range + g.range;
            if (r < max_range) addReturn(r, g.depth, hitPower(g, r) * dbToLinear(-o.ghost_attenuation_db));
          }
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
    const bool saturated = rng.chance(o.saturation_probability);
    const double beam_angle = pose.z() + scan.angle[a];
    const Eigen::Vector2d dir(std::cos(beam_angle), std::sin(beam_angle));
    std::uint8_t* row = scan.row(a);
    for (int b = 0; b < B; ++b) {
      const double r = (b + offset) * res;
      double s = signal[b];
      if (r < 3.0) s += leakage * std::exp(-r / 0.5);
      // Noise and Rayleigh ground clutter add up to one exponential of their summed mean.
      double mean = noise_lin[b];
      if (clutter > 0 && r < occluded) {
        const double c = groundClutter(seed, origin + r * dir, o.ground_clutter_cover);
        if (c > 0) mean += clutter * range_gain[b] * c;
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
      if (o.display_compression < 1.0 && db > o.display_knee_db) db = o.display_knee_db + (db - o.display_knee_db) * o.display_compression;
      const double v = o.noise_display_level + db / o.display_db_range;
      row[b] = static_cast<std::uint8_t>(std::lround(std::min(std::max(v, 0.0), 1.0) * 255.0));
    }
  }
}

SequenceSummary writeScanningSequence(const std::string& dir, const SimTrajectory& ego, const WorldOptions& world_options,
                                      const ScanningOptions& options, const SequenceOptions& sequence) {
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
    writing = std::async(std::launch::async, [&scan, &oxford, &sequence, path = (fs::path(dir) / "radar" / (std::to_string(stamp) + ".png")).string()] {
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
      OxfordRelativePose row;
      row.source = stamp;
      row.destination = previous_stamp;
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
  double x, y;        // sensor frame
  double vr;          // radial velocity, positive receding
  double rcs;
  bool moving;
  double sx, sy;      // position standard deviations in the sensor frame
  double vr_world;    // the target's own radial velocity (for vx_comp / vy_comp)
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
std::array<double, 4> quaternionYaw(double yaw) { return {std::cos(0.5 * yaw), 0.0, 0.0, std::sin(0.5 * yaw)}; }

}  // namespace

SequenceSummary writeAutomotiveSequence(const std::string& dir, const SimTrajectory& ego, const WorldOptions& world_options,
                                        const AutomotiveOptions& o, const SequenceOptions& sequence) {
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
    tables.addCalibratedSensor(calib_token, sensor_token, {mount.x, mount.y, mount.z}, quaternionYaw(mount.yaw_deg * kDeg));
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
          const double p = std::min(0.95, o.detection_probability * through * std::clamp(0.5 + m.rcs_dbsm / 20.0, 0.2, 1.5));
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
        Detection d{r * std::cos(a), r * std::sin(a), rng.uniform(-6.0, 6.0), rng.uniform(-10.0, 5.0), true,
                    o.range_sigma, r * o.azimuth_sigma_deg * kDeg, 0.0};
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
      std::sort(dets.begin(), dets.end(), [](const Detection& a, const Detection& b) {
        return std::hypot(a.x, a.y) < std::hypot(b.x, b.y);
      });
      total_detections += dets.size();

      const std::int64_t stamp = stampOf(t);
      const std::string folder = key[k] ? "samples" : "sweeps";
      const std::string filename = folder + "/" + mount.channel + "/" + sequence.scene_name + "__" + mount.channel + "__" +
                                   std::to_string(stamp) + ".pcd";
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
  tables.addScene(scene_token, log_token, nsamples, token(seed, 3, 0), token(seed, 3, nsamples - 1), sequence.scene_name,
                  "radar_sim automotive sequence, seed " + std::to_string(seed) + ", " + std::to_string(total_detections) +
                      " detections");
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
