#include "radar_ndt/pipeline/scanning_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>
#include <stdexcept>
#include <sys/stat.h>

#include "radar_ndt/frontend/voxel_merge.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/se2.h"
#include "detail/run_timing.h"

namespace radar_ndt {

using detail::Clock;
using detail::median;
namespace {
double ms(Clock::time_point a, Clock::time_point b) { return detail::msBetween(a, b); }
bool exists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}
std::string baseName(std::string dir) {
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  const auto slash = dir.find_last_of('/');
  return slash == std::string::npos ? dir : dir.substr(slash + 1);
}
}  // namespace

ScanFormat parseScanFormat(const std::string& name) {
  if (name == "oxford") return ScanFormat::Oxford;
  if (name == "radiate") return ScanFormat::Radiate;
  throw std::invalid_argument("unknown scanning format '" + name + "' (oxford, radiate)");
}

const char* toString(ScanFormat f) { return f == ScanFormat::Oxford ? "oxford" : "radiate"; }

ScanningSequence::ScanningSequence(const std::string& dir, ScanFormat format, const Options& options)
    : dir_(dir), name_(baseName(dir)), format_(format), options_(options) {
  if (format == ScanFormat::Oxford) {
    const std::string index = dir + "/radar.timestamps";
    if (!exists(index)) throw IoError(index, "missing: an Oxford-layout sequence has radar.timestamps and radar/<stamp>.png");
    std::vector<IoError> skipped;
    for (const OxfordStamp& s : readOxfordTimestamps(index, &skipped)) {
      stamps_.push_back(s.stamp);
      paths_.push_back(dir + "/radar/" + std::to_string(s.stamp) + ".png");
    }
    for (const IoError& e : skipped) index_problems_.push_back(e.what());
    const std::string gt_path = dir + "/gt/radar_odometry.csv";
    if (exists(gt_path)) {
      const std::vector<OxfordRelativePose> rows = readOxfordRadarOdometry(gt_path);
      // Chain the relative motions from the first row's destination scan. Oxford axes (x forward,
      // y right, z down) → vehicle axes (x forward, y left, z up): y and yaw change sign.
      Pose2 pose = Pose2::Zero();
      if (!rows.empty()) {
        ground_truth_.stamps.push_back(1e-6 * static_cast<double>(rows.front().destination));
        ground_truth_.poses.push_back(toIsometry3(pose));
      }
      for (const auto& r : rows) {
        pose = compose(pose, Pose2(r.x, -r.y, -r.yaw));
        ground_truth_.stamps.push_back(1e-6 * static_cast<double>(r.source));
        ground_truth_.poses.push_back(toIsometry3(pose));
      }
    }
  } else {
    const std::string index = dir + "/Navtech_Polar.txt";
    if (!exists(index)) throw IoError(index, "missing: a RADIATE sequence has Navtech_Polar.txt and Navtech_Polar/<frame>.png");
    std::vector<IoError> skipped;
    for (const RadiateFrame& f : readRadiateFrameTimes(index, &skipped)) {
      char name[32];
      std::snprintf(name, sizeof name, "%06d.png", f.frame);
      stamps_.push_back(f.stamp_us);
      paths_.push_back(dir + "/Navtech_Polar/" + name);
    }
    for (const IoError& e : skipped) index_problems_.push_back(e.what());
  }
  if (stamps_.empty()) throw IoError(dir, "the sequence lists no scans");
  std::vector<double> d;
  for (std::size_t k = 1; k < stamps_.size(); ++k) d.push_back(1e-6 * static_cast<double>(stamps_[k] - stamps_[k - 1]));
  period_s_ = median(d);
}

PolarScan ScanningSequence::load(std::size_t k) const {
  if (format_ == ScanFormat::Oxford) {
    PolarScan scan = readOxfordPolarPng(paths_[k], options_.oxford);
    scan.stamp = stamps_[k];  // the index's stamp is the scan's reference time
    return scan;
  }
  return readRadiatePolarPng(paths_[k], stamps_[k], options_.radiate);
}

namespace {
/// A decoded and thresholded scan, or why it could not be.
struct Prepared {
  std::size_t index = 0;
  pcl::PointCloud<PointRadar>::Ptr cloud;
  std::string problem;
  double read_ms = 0, front_end_ms = 0;
};

Prepared prepare(const ScanningSequence& sequence, const PowerThreshold& front_end, std::size_t k, double voxel) {
  Prepared p;
  p.index = k;
  try {
    const auto t0 = Clock::now();
    const PolarScan scan = sequence.load(k);
    const auto t1 = Clock::now();
    p.cloud.reset(new pcl::PointCloud<PointRadar>);
    front_end.compute(scan, *p.cloud);
    if (voxel > 0) {
      pcl::PointCloud<PointRadar>::Ptr merged(new pcl::PointCloud<PointRadar>);
      mergeVoxels(*p.cloud, voxel, *merged);
      p.cloud = merged;
    }
    p.read_ms = ms(t0, t1);
    p.front_end_ms = ms(t1, Clock::now());
  } catch (const std::exception& e) {
    p.cloud.reset();
    p.problem = e.what();
  }
  return p;
}

/// The ground-truth pose at time t (s), linear between its neighbours; false outside its span.
bool poseAt(const Trajectory& gt, double t, Pose2* out) {
  if (gt.stamps.empty() || t < gt.stamps.front() - 1e-6 || t > gt.stamps.back() + 1e-6) return false;
  const auto it = std::lower_bound(gt.stamps.begin(), gt.stamps.end(), t - 1e-6);
  const std::size_t i = static_cast<std::size_t>(it - gt.stamps.begin());
  if (i == 0 || std::abs(gt.stamps[i] - t) < 1e-6) {
    *out = toPose2(gt.poses[i]);
    return true;
  }
  const Pose2 a = toPose2(gt.poses[i - 1]), b = toPose2(gt.poses[i]);
  const double u = (t - gt.stamps[i - 1]) / (gt.stamps[i] - gt.stamps[i - 1]);
  const Pose2 d = between(a, b);
  *out = compose(a, Pose2(u * d.x(), u * d.y(), u * d.z()));
  return true;
}
}  // namespace

ScanningRunResult runScanningOdometry(const ScanningSequence& sequence, const ScanningRunOptions& options,
                                      const std::function<void(std::size_t, std::size_t)>& progress, const ScanCallback& on_scan) {
  if (options.start >= sequence.size())
    throw std::invalid_argument("start scan " + std::to_string(options.start) + " is past the sequence's " +
                                std::to_string(sequence.size()) + " scans");
  const std::size_t end =
      options.max_scans > 0 ? std::min(sequence.size(), options.start + options.max_scans) : sequence.size();
  const std::size_t n = end - options.start;
  const PowerThreshold front_end(options.front_end);  // used by one thread at a time (the futures chain)
  RadarRegistration::Ptr matcher = makeMatcher(options.method, options.odometry.scanning.grid);
  if (auto* ours = dynamic_cast<WeightedNDT2D<PointRadar, PointRadar>*>(matcher.get())) ours->setCellLookup(options.cell_lookup);
  Odometry odometry(options.odometry, matcher);

  ScanningRunResult result;
  result.problems = sequence.indexProblems();
  result.sequence = sequence.name();
  result.format = sequence.format();
  result.period_s = sequence.periodSeconds();
  std::vector<double> read, fe, match, total, points;
  const auto wall0 = Clock::now();
  std::future<Prepared> next;
  const double voxel = options.method == Method::PwNdt ? 0.0 : options.pcl_voxel_size;
  auto launch = [&](std::size_t k) {
    return std::async(options.prefetch ? std::launch::async : std::launch::deferred,
                      [&sequence, &front_end, k, voxel]() { return prepare(sequence, front_end, k, voxel); });
  };
  if (n > 0) next = launch(options.start);
  std::int64_t last_stamp_us = 0;  // of the last scan that was matched (or dead-reckoned)
  for (std::size_t k = options.start; k < end; ++k) {
    Prepared p = next.get();
    if (k + 1 < end) next = launch(k + 1);
    if (!p.cloud) {
      result.problems.push_back("scan " + std::to_string(k) + ": " + p.problem + " (bridged with the motion model)");
      odometry.bridge(sequence.stamp(k));
    } else {
      const OdometryStep& step = odometry.addScan(ScanFrame{sequence.stamp(k), p.cloud});
      read.push_back(p.read_ms);
      fe.push_back(p.front_end_ms);
      match.push_back(step.match_ms);
      total.push_back(p.read_ms + p.front_end_ms + step.match_ms);
      points.push_back(static_cast<double>(p.cloud->size()));
      if (on_scan && step.status != StepStatus::Skipped) {
        // This scan at its reference time (lastCloud() is the keyframe, which may be an older scan).
        pcl::PointCloud<PointRadar> at_reference;
        const double dt = 1e-6 * static_cast<double>(step.timestamp_us - last_stamp_us);
        if (options.odometry.scanning.motion_compensation && step.status != StepStatus::First && dt > 0)
          compensateMotion(*p.cloud, velocityOf(step.motion, dt), at_reference);
        else
          at_reference = *p.cloud;
        on_scan(k, step, at_reference);
      }
      if (step.status != StepStatus::Skipped) last_stamp_us = step.timestamp_us;
    }
    if (progress) progress(k - options.start + 1, n);
  }
  result.wall_s = std::chrono::duration<double>(Clock::now() - wall0).count();
  result.scans_per_second = result.wall_s > 0 ? static_cast<double>(n) / result.wall_s : 0.0;
  result.median_ms = {median(read), median(fe), 0.0, median(match)};
  result.median_total_ms = median(total);
  result.median_points = median(points);
  result.steps = odometry.steps();
  result.counters = odometry.counters();
  result.estimate = odometry.trajectory();

  // Ground truth at the estimate's stamps, re-based on the first one.
  const Trajectory& gt = sequence.groundTruth();
  if (!gt.empty() && !result.estimate.empty()) {
    Pose2 origin;
    if (poseAt(gt, result.estimate.stamps.front(), &origin)) {
      for (std::size_t i = 0; i < gt.size(); ++i) {
        if (gt.stamps[i] + 1e-6 < result.estimate.stamps.front()) continue;
        if (gt.stamps[i] - 1e-6 > result.estimate.stamps.back()) break;
        result.ground_truth.stamps.push_back(gt.stamps[i]);
        result.ground_truth.poses.push_back(toIsometry3(between(origin, toPose2(gt.poses[i]))));
      }
    }
  }
  return result;
}

}  // namespace radar_ndt
