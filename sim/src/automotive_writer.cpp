// The simulator's nuScenes-layout output: ARS408 automotive radars at nuScenes' five mountings,
// each sweep's detections rendered (returns, noise, clutter, multipath, clusters) and written as
// the dataset's PCD files and JSON tables.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/nuscenes_writer.h"
#include "radar_ndt/sim/radar_sim.h"
#include "sim_common.h"
#include "sim_random.h"

namespace radar_ndt {
namespace sim {
namespace fs = std::filesystem;
using detail::kDeg;
using detail::progressLine;
using detail::token;
using detail::toMicros;

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

/// Detections of one sweep before merging: each surface return detected with a probability by its
/// material, measured with the ARS408's noise, vehicles with multipath ghosts.
void detectReturns(const World& world, const Pose2& sensor, const Eigen::Vector2d& v_sensor, double t,
                   const std::vector<int>& movers, const AutomotiveOptions& o, Random& rng, std::vector<Hit>& hits,
                   std::vector<Detection>& raw) {
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
}

/// Clutter: false detections anywhere in the near field of view.
void addClutter(const AutomotiveOptions& o, Random& rng, std::vector<Detection>& raw) {
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
}

/// Returns closer than the cluster distance merge into one detection (the strongest); at most
/// max_detections, nearest first.
std::vector<Detection> mergeClusters(std::vector<Detection> raw, const AutomotiveOptions& o) {
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
  return dets;
}

/// One sweep of radar `mount` at time t: the vehicle's pose there, the detections as written.
std::vector<Detection> renderSweep(const World& world, const SimTrajectory& ego, const Mounting& mount, double t,
                                   const AutomotiveOptions& o, Random& rng, std::vector<Hit>& hits, Pose2* pose_out) {
  const Pose2 pose = ego.at(t);
  const Pose2 sensor = compose(pose, Pose2(mount.x, mount.y, mount.yaw_deg * kDeg));
  const Eigen::Vector3d vel = ego.velocity(t);  // body (vx, vy, ω)
  // Sensor velocity in the world: v + ω × r, rotated by the vehicle heading.
  const Eigen::Vector2d v_body(vel.x() - vel.z() * mount.y, vel.y() + vel.z() * mount.x);
  const double ch = std::cos(pose.z()), sh = std::sin(pose.z());
  const Eigen::Vector2d v_sensor(ch * v_body.x() - sh * v_body.y(), sh * v_body.x() + ch * v_body.y());
  const std::vector<int> movers = world.activeMovers(sensor.head<2>(), o.far_range + 5.0, t);
  std::vector<Detection> raw;
  detectReturns(world, sensor, v_sensor, t, movers, o, rng, hits, raw);
  addClutter(o, rng, raw);
  *pose_out = pose;
  return mergeClusters(std::move(raw), o);
}

/// One radar's sweep times: its own phase (the front one, c = 0, starts the cycle clock) and jitter.
std::vector<double> sweepTimes(std::size_t c, double t0, double duration, std::size_t frames,
                               const AutomotiveOptions& o, std::uint64_t seed, Random& phase_rng) {
  const double phase = c == 0 ? 0.0 : phase_rng.uniform(0.0, o.period);
  const std::size_t sweeps = c == 0 ? frames : static_cast<std::size_t>((duration - phase) / o.period);
  std::vector<double> times(sweeps);
  Random jitter_rng(seed, 0xa071000000000000ULL + c);
  for (std::size_t k = 0; k < sweeps; ++k)
    times[k] = t0 + o.jitter + phase + k * o.period + jitter_rng.uniform(-o.jitter, o.jitter);
  return times;
}

/// Key frames: per sample time (every 0.5 s), the sweep nearest it, within half a period.
std::vector<bool> keyFrames(const std::vector<double>& times, double t0, std::size_t nsamples, double period) {
  const std::size_t sweeps = times.size();
  std::vector<bool> key(sweeps, false);
  for (std::size_t i = 0; i < nsamples; ++i) {
    std::size_t best = sweeps;
    for (std::size_t k = 0; k < sweeps; ++k)
      if (best == sweeps || std::abs(times[k] - (t0 + 0.5 * i)) < std::abs(times[best] - (t0 + 0.5 * i))) best = k;
    if (best < sweeps && std::abs(times[best] - (t0 + 0.5 * i)) < 0.5 * period) key[best] = true;
  }
  return key;
}

/// Writes the dataroot: the scene's samples, then each radar's sweeps (PCD files) with their
/// tables, then the log and the scene.
class AutomotiveWriter {
 public:
  AutomotiveWriter(const std::string& dir, const SimTrajectory& ego, const World& world, const AutomotiveOptions& o,
                   const SequenceOptions& sequence, std::uint64_t seed, std::size_t frames)
      : dir_(dir),
        ego_(ego),
        world_(world),
        o_(o),
        sequence_(sequence),
        seed_(seed),
        frames_(frames),
        t0_(ego.stamps()[sequence.start]),
        duration_(frames * o.period),
        nsamples_(static_cast<std::size_t>(duration_ / 0.5) + 1) {}

  void writeSamples() {
    // Samples (key frames) every 0.5 s, as in nuScenes.
    for (std::size_t i = 0; i < nsamples_; ++i)
      tables_.addSample(token(seed_, 3, i), stampOf(t0_ + 0.5 * i), i ? token(seed_, 3, i - 1) : "",
                        i + 1 < nsamples_ ? token(seed_, 3, i + 1) : "", token(seed_, 2, 0));
  }

  void writeRadar(std::size_t c, Random& phase_rng) {
    const Mounting& mount = kMountings[c];
    const std::string sensor_token = token(seed_, 4, c), calib_token = token(seed_, 5, c);
    tables_.addSensor(sensor_token, mount.channel, "radar");
    tables_.addCalibratedSensor(calib_token, sensor_token, {mount.x, mount.y, mount.z},
                                quaternionYaw(mount.yaw_deg * kDeg));
    // Unsynchronised radars: each its own phase; the front one starts the cycle clock.
    const std::vector<double> times = sweepTimes(c, t0_, duration_, frames_, o_, seed_, phase_rng);
    const std::size_t sweeps = times.size();
    std::vector<std::size_t> sample_of(sweeps);
    for (std::size_t k = 0; k < sweeps; ++k)
      sample_of[k] =
          std::min<std::size_t>(nsamples_ - 1, static_cast<std::size_t>(std::lround((times[k] - t0_) / 0.5)));
    const std::vector<bool> key = keyFrames(times, t0_, nsamples_, o_.period);
    for (std::size_t k = 0; k < sweeps; ++k) {
      Random rng(seed_, 0xa072000000000000ULL + (static_cast<std::uint64_t>(c) << 32) + k);
      Pose2 pose;
      const std::vector<Detection> dets = renderSweep(world_, ego_, mount, times[k], o_, rng, hits_, &pose);
      total_detections_ += dets.size();
      writeSweep(mount, calib_token, stampOf(times[k]), key[k], sample_of[k], k, sweeps, pose, dets);
      if (c == 0) progressLine(sequence_.progress, "radar_sim: front sweep", k, sweeps);
    }
  }

  void writeTables() {
    const std::string log_token = token(seed_, 1, 0), scene_token = token(seed_, 2, 0);
    tables_.addLog(log_token, "radar_sim-seed-" + std::to_string(seed_), "radar_sim", "", "simulated");
    tables_.addScene(scene_token, log_token, nsamples_, token(seed_, 3, 0), token(seed_, 3, nsamples_ - 1),
                     sequence_.scene_name,
                     "radar_sim automotive sequence, seed " + std::to_string(seed_) + ", " +
                         std::to_string(total_detections_) + " detections");
    tables_.write((fs::path(dir_) / "v1.0-sim").string());
  }

  double duration() const { return duration_; }

 private:
  std::int64_t stampOf(double t) const { return sequence_.start_stamp_us + toMicros(t - t0_); }

  void writeSweep(const Mounting& mount, const std::string& calib_token, std::int64_t stamp, bool key,
                  std::size_t sample, std::size_t k, std::size_t sweeps, const Pose2& pose,
                  const std::vector<Detection>& dets) {
    const std::string folder = key ? "samples" : "sweeps";
    const std::string filename = folder + "/" + mount.channel + "/" + sequence_.scene_name + "__" + mount.channel +
                                 "__" + std::to_string(stamp) + ".pcd";
    writeNuScenesRadarPcd((fs::path(dir_) / filename).string(), toPcdPoints(dets, o_.doppler_sigma));
    const std::string ego_token = token(seed_, 6, data_index_);
    tables_.addEgoPose(ego_token, stamp, quaternionYaw(pose.z()), {pose.x(), pose.y(), 0.0});
    tables_.addSampleData(token(seed_, 7, data_index_), token(seed_, 3, sample), ego_token, calib_token, stamp, key,
                          filename, k ? token(seed_, 7, data_index_ - 1) : "",
                          k + 1 < sweeps ? token(seed_, 7, data_index_ + 1) : "");
    ++data_index_;
  }

  const std::string& dir_;
  const SimTrajectory& ego_;
  const World& world_;
  const AutomotiveOptions& o_;
  const SequenceOptions& sequence_;
  const std::uint64_t seed_;
  const std::size_t frames_;
  const double t0_, duration_;
  const std::size_t nsamples_;
  NuScenesTableWriter tables_;
  std::vector<Hit> hits_;
  std::size_t total_detections_ = 0, data_index_ = 0;
};

/// The front radar's sweeps to write from `sequence.start`, at least 2; the output folders created.
std::size_t prepareAutomotiveOutput(const std::string& dir, const SimTrajectory& ego, const AutomotiveOptions& o,
                                    const SequenceOptions& sequence) {
  if (sequence.start >= ego.size()) throw std::invalid_argument("radar_sim: --start is past the trajectory's end");
  const double t0 = ego.stamps()[sequence.start];
  const double available = ego.endTime() - t0 - o.period - 2.0 * o.jitter;
  const std::size_t max_frames = available > 0 ? static_cast<std::size_t>(available / o.period) : 0;
  const std::size_t frames = sequence.frames == 0 ? max_frames : std::min(sequence.frames, max_frames);
  if (frames < 2) throw std::invalid_argument("radar_sim: the trajectory is too short for 2 radar cycles");
  std::error_code ec;
  fs::create_directories(fs::path(dir) / "v1.0-sim", ec);
  for (const auto& m : kMountings) {
    fs::create_directories(fs::path(dir) / "samples" / m.channel, ec);
    fs::create_directories(fs::path(dir) / "sweeps" / m.channel, ec);
  }
  if (ec) throw IoError(dir, "cannot create the output directories: " + ec.message());
  return frames;
}

}  // namespace

SequenceSummary writeAutomotiveSequence(const std::string& dir, const SimTrajectory& ego,
                                        const WorldOptions& world_options, const AutomotiveOptions& o,
                                        const SequenceOptions& sequence) {
  const auto wall = std::chrono::steady_clock::now();
  world_options.validate();
  o.validate();
  sequence.validate();
  const std::size_t frames = prepareAutomotiveOutput(dir, ego, o, sequence);
  const World world = World::generate(ego, world_options);
  const std::uint64_t seed = world_options.seed;
  Random phase_rng(seed, 0xa070000000000000ULL);
  AutomotiveWriter writer(dir, ego, world, o, sequence, seed, frames);
  writer.writeSamples();
  for (std::size_t c = 0; c < kMountings.size(); ++c) writer.writeRadar(c, phase_rng);
  writer.writeTables();

  return detail::summarize(ego, ego.stamps()[sequence.start], frames, writer.duration(), wall);
}

}  // namespace sim
}  // namespace radar_ndt
