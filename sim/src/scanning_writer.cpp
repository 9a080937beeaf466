// The simulator's Oxford-layout output: a scanning sequence rendered scan by scan (renderScan) and
// written as the dataset lays it out, with its ground truth.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <future>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/boreas_ground_truth.h"
#include "radar_ndt/io/boreas_imu.h"
#include "radar_ndt/io/boreas_scan.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/oxford_ground_truth.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/sim/radar_sim.h"
#include "sim_common.h"

namespace radar_ndt {
namespace sim {
namespace fs = std::filesystem;
using detail::toMicros;

namespace {

/// The sequence's ground truth as it is written: the Oxford CSV's rows and the KITTI poses.
struct GroundTruthWriter {
  std::vector<OxfordStamp> stamps;
  std::vector<OxfordRelativePose> rows;
  std::ostringstream poses;
  Pose2 first = Pose2::Zero(), previous = Pose2::Zero();
  std::int64_t previous_stamp = 0;

  GroundTruthWriter() { poses << std::setprecision(9); }

  /// Scan k at `stamp` with the vehicle at `pose`.
  void add(std::size_t k, std::int64_t stamp, const Pose2& pose, double sweep_period) {
    stamps.push_back({stamp, true});
    if (k == 0) first = pose;
    const Pose2 rel = between(first, pose);
    const double c = std::cos(rel.z()), s = std::sin(rel.z());
    poses << c << ' ' << -s << " 0 " << rel.x() << ' ' << s << ' ' << c << " 0 " << rel.y() << " 0 0 1 0\n";
    if (k > 0) {
      const Pose2 d = between(previous, pose);  // the later scan in the earlier one's frame
      // As the dataset writes them: source/destination_timestamp half a sweep after the scans'
      // radar timestamps (its poses are mid-sweep), the radar timestamps in their own columns.
      const std::int64_t half_sweep = toMicros(0.5 * sweep_period);
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
  }

  void write(const std::string& dir) const {
    writeOxfordTimestamps((fs::path(dir) / "radar.timestamps").string(), stamps);
    writeOxfordRadarOdometry((fs::path(dir) / "gt" / "radar_odometry.csv").string(), rows);
    writeFileAtomically((fs::path(dir) / "gt" / "poses.txt").string(), poses.str());
  }
};

/// Two scan buffers: scan k is encoded and written on a second thread while scan k+1 is rendered.
class BackgroundWriter {
 public:
  PolarScan& buffer(std::size_t k) { return buffers_[k % 2]; }
  /// Waits for the last write (rethrowing its failure), then starts `write(scan)`.
  void write(const PolarScan& scan, std::function<void(const PolarScan&)> write) {
    finish();
    writing_ = std::async(std::launch::async, [&scan, write = std::move(write)] { write(scan); });
  }
  void finish() {
    if (writing_.valid()) writing_.get();
  }

 private:
  PolarScan buffers_[2];
  std::future<void> writing_;
};

/// The frames to write from `sequence.start`, at least 2; the output folders created.
std::size_t prepareScanningOutput(const std::string& dir, const SimTrajectory& ego, const SequenceOptions& sequence) {
  if (sequence.start >= ego.size()) throw std::invalid_argument("radar_sim: --start is past the trajectory's end");
  const std::size_t available = ego.size() - sequence.start;
  const std::size_t frames = sequence.frames == 0 ? available : std::min(sequence.frames, available);
  if (frames < 2) throw std::invalid_argument("radar_sim: a sequence needs at least 2 frames");
  std::error_code ec;
  fs::create_directories(fs::path(dir) / "radar", ec);
  fs::create_directories(fs::path(dir) / "gt", ec);
  if (ec) throw IoError(dir, "cannot create the output directories: " + ec.message());
  return frames;
}

}  // namespace

SequenceSummary writeScanningSequence(const std::string& dir, const SimTrajectory& ego,
                                      const WorldOptions& world_options, const ScanningOptions& options,
                                      const SequenceOptions& sequence) {
  const auto wall = std::chrono::steady_clock::now();
  world_options.validate();
  options.validate();
  sequence.validate();
  const std::size_t frames = prepareScanningOutput(dir, ego, sequence);
  const World world = World::generate(ego, world_options);
  const double t0 = ego.stamps()[sequence.start];
  GroundTruthWriter truth;
  BackgroundWriter writer;
  const OxfordPolarOptions oxford;
  for (std::size_t k = 0; k < frames; ++k) {
    const double t = ego.stamps()[sequence.start + k];
    PolarScan& scan = writer.buffer(k);
    renderScan(world, ego, t, world_options.seed, k, options, scan);
    const std::int64_t stamp = sequence.start_stamp_us + toMicros(t - t0);
    const std::int64_t base = toMicros(t);
    for (auto& s : scan.stamp_us) s = stamp + (s - base);
    scan.stamp = stamp;
    writer.write(scan,
                 [&oxford, &sequence, path = (fs::path(dir) / "radar" / (std::to_string(stamp) + ".png")).string()](
                     const PolarScan& s) { writeOxfordPolarPng(path, s, oxford, sequence.png_compression); });
    truth.add(k, stamp, ego.at(t), options.sweep_period);
    detail::progressLine(sequence.progress, "radar_sim: scan", k, frames);
  }
  writer.finish();
  truth.write(dir);

  return detail::summarize(ego, t0, frames, ego.stamps()[sequence.start + frames - 1] - t0, wall);
}

void applyChirpShift(PolarScan& scan, const SimTrajectory& ego, double t0, std::int64_t stamp0_us, double beta) {
  if (scan.chirp_up.size() != static_cast<std::size_t>(scan.azimuths) || beta == 0.0) return;
  shiftRanges(scan, [&](int a) {
    const Eigen::Vector3d v = ego.velocity(t0 + 1e-6 * static_cast<double>(scan.stamp_us[a] - stamp0_us));
    // Static scenery along the beam recedes at minus the sensor's velocity along it.
    const double radial = -(v.x() * std::cos(scan.angle[a]) + v.y() * std::sin(scan.angle[a]));
    return (scan.chirp_up[a] ? 1.0 : -1.0) * beta * radial;
  });
}

SequenceSummary writeBoreasSequence(const std::string& dir, const SimTrajectory& ego, const WorldOptions& world_options,
                                    const ScanningOptions& options, const SequenceOptions& sequence,
                                    const BoreasLayoutOptions& layout) {
  const auto wall = std::chrono::steady_clock::now();
  world_options.validate();
  options.validate();
  sequence.validate();
  const std::size_t frames = prepareScanningOutput(dir, ego, sequence);
  std::error_code ec;
  fs::create_directories(fs::path(dir) / "applanix", ec);
  if (ec) throw IoError(dir, "cannot create applanix/: " + ec.message());
  const World world = World::generate(ego, world_options);
  const double t0 = ego.stamps()[sequence.start];
  // The dataset names a scan by row floor(M / 2) − 1: the sweep starts that many azimuths earlier.
  const int middle = std::max(0, options.azimuths / 2 - 1);
  const double lead = middle * options.sweep_period / options.azimuths;
  GroundTruthWriter truth;  // for gt/poses.txt only: Boreas has no Oxford index or CSV
  std::vector<BoreasPose> poses;
  BackgroundWriter writer;
  for (std::size_t k = 0; k < frames; ++k) {
    const double t = ego.stamps()[sequence.start + k];
    PolarScan& scan = writer.buffer(k);
    renderScan(world, ego, t - lead, world_options.seed, k, options, scan);
    const std::int64_t base = toMicros(t - lead), start = sequence.start_stamp_us + toMicros(t - lead - t0);
    for (auto& s : scan.stamp_us) s = start + (s - base);
    scan.stamp = scan.stamp_us[static_cast<std::size_t>(std::min(middle, scan.azimuths - 1))];
    scan.chirp_up.clear();
    if (layout.chirp_flags) {
      for (int a = 0; a < scan.azimuths; ++a) scan.chirp_up.push_back(a % 2 == 0 ? 0 : 1);
      applyChirpShift(scan, ego, t0, sequence.start_stamp_us, layout.chirp_beta);
    }
    writer.write(scan, [&sequence, path = (fs::path(dir) / "radar" / (std::to_string(scan.stamp) + ".png")).string(),
                        encoder_size = options.encoder_size](const PolarScan& s) {
      writeBoreasPolarPng(path, s, encoder_size, sequence.png_compression);
    });
    const Pose2 pose = ego.at(t);
    const Eigen::Vector3d v = ego.velocity(t);
    truth.add(k, scan.stamp, pose, options.sweep_period);
    poses.push_back(boreasPoseFromPlanar(1e-6 * static_cast<double>(scan.stamp), pose.x() + layout.enu_east,
                                         pose.y() + layout.enu_north, pose.z(), v.x(), v.y(), v.z()));
    detail::progressLine(sequence.progress, "radar_sim: scan", k, frames);
  }
  writer.finish();
  writeBoreasPoses((fs::path(dir) / "applanix" / "radar_poses.csv").string(), poses);
  if (layout.imu) {
    // The gyro from a second before the first sweep starts to a second after the last ends.
    const double t_first = t0 - lead, t_last = ego.stamps()[sequence.start + frames - 1] + options.sweep_period;
    const double t_begin = std::max(ego.startTime(), t_first - 1.0), t_end = std::min(ego.endTime(), t_last + 1.0);
    writeBoreasImu(
        (fs::path(dir) / "applanix" / "imu.csv").string(),
        simulateImu(ego, t_begin, t_end, t0, sequence.start_stamp_us, layout.imu_options, world_options.seed));
  }
  writeFileAtomically((fs::path(dir) / "gt" / "poses.txt").string(), truth.poses.str());

  return detail::summarize(ego, t0, frames, ego.stamps()[sequence.start + frames - 1] - t0, wall);
}

}  // namespace sim
}  // namespace radar_ndt
