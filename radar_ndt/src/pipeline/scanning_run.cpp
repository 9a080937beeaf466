#include "radar_ndt/pipeline/scanning_run.h"
#include "radar_ndt/io/io_error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "detail/run_timing.h"
#include "pipeline/ordered_pipeline.h"
#include "pipeline/scan_pipeline.h"
#include "radar_ndt/odometry/matcher_registry.h"
#include "radar_ndt/odometry/motion_compensation.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

using detail::Clock;
using detail::median;
using detail::msBetween;

void ScanningRunOptions::validate() const {
  checkFields(*this, "ScanningRunOptions");
  if (findMatcher(matcher.method).uses.automotiveOnly()) {
    std::string others;
    for (const std::string& name : matcherNames())
      if (!findMatcher(name).uses.automotiveOnly()) others += (others.empty() ? "" : ", ") + name;
    throw std::invalid_argument("method " + matcher.method +
                                " needs Doppler or a car's CAN bus, which scanning sequences do not have (" + others +
                                ")");
  }
}

namespace {

/// Per scan samples of the stage times and point counts, for the medians.
struct ScanSamples {
  std::vector<double> read, front_end, match, total, points;
  void add(const detail::PreparedScan& p, const OdometryStep& step) {
    read.push_back(p.read_ms);
    front_end.push_back(p.front_end_ms);
    match.push_back(step.match_ms);
    total.push_back(p.read_ms + p.front_end_ms + step.match_ms);
    points.push_back(static_cast<double>(p.cloud->size()));
  }
};

ScanningRunResult startResult(const ScanSource& sequence, const ScanningRunOptions& options) {
  ScanningRunResult result;
  result.problems = sequence.indexProblems();
  result.sequence = sequence.name();
  result.format = sequence.formatName();
  result.method = options.matcher.method;
  result.threads = detail::resolveThreads(options.threads);
  result.period_s = sequence.periodSeconds();
  return result;
}

/// The sequence's gyro for `odometry` (Boreas: applanix/imu.csv; a bag: its IMU topic); a
/// sequence without one is run without it, and the problems say so once.
void attachGyro(const ScanSource& sequence, ScanningOdometry& odometry, std::vector<std::string>& problems) {
  std::string why_not;
  std::optional<VehicleSignals> imu = sequence.gyro(&why_not);
  if (!imu) {
    problems.push_back(why_not + ": the run goes on without a gyro");
    return;
  }
  const std::int64_t first = sequence.stamp(0), last = sequence.stamp(sequence.size() - 1);
  if (!imu->yaw_rate.covers(first, last))
    problems.push_back(imu->source + ": the gyro does not cover every scan's time (its ends are held beyond it)");
  odometry.setYawRate(std::move(imu->yaw_rate));
}

/// A step no match was made for, as a problem naming the scan's file and why; "" for the others.
std::string problemOf(const OdometryStep& step, const ScanningOdometryOptions& options, const std::string& prior) {
  if (step.status == StepStatus::DeadReckoned && step.too_few_points)
    return "too few points to match (" + std::to_string(step.source_points) + " in the scan, " +
           std::to_string(step.target_points) + " in its keyframe; at least " + std::to_string(options.min_points) +
           " each): " + prior;
  if (step.status != StepStatus::Fallback) return "";
  std::string why;
  auto add = [&why](int n, const char* what) {
    if (n) why += (why.empty() ? "" : ", ") + std::to_string(n) + " " + what;
  };
  add(step.attempts_poor_fit, "fitting far worse than recent scans");
  add(step.attempts_rejected, "refused by the motion prior");
  add(step.attempts_not_converged, "not converged");
  return "no match passed (" + (why.empty() ? std::string("no power weights") : why) + "): " + prior;
}

/// The sequence's ground truth from the estimate's first stamp to its last, re-based so that the
/// first is the identity; empty without ground truth there.
Trajectory rebasedGroundTruth(const Trajectory& gt, const Trajectory& estimate) {
  Trajectory out;
  Eigen::Isometry3d origin_3d;
  if (gt.empty() || estimate.empty() || !gt.poseAt(estimate.stamps.front(), &origin_3d)) return out;
  const Pose2 origin = toPose2(origin_3d);
  for (std::size_t i = 0; i < gt.size(); ++i) {
    if (gt.stamps[i] + 1e-6 < estimate.stamps.front()) continue;
    if (gt.stamps[i] - 1e-6 > estimate.stamps.back()) break;
    out.stamps.push_back(gt.stamps[i]);
    out.poses.push_back(toIsometry3(between(origin, toPose2(gt.poses[i]))));
  }
  return out;
}

/// The scan at its reference time, for the caller's callback (the keyframe may be an older scan):
/// moved with the step's velocity when compensation is on.
pcl::PointCloud<PointRadar> atReferenceTime(const pcl::PointCloud<PointRadar>& scan, const OdometryStep& step,
                                            std::int64_t previous_stamp_us, bool compensate) {
  pcl::PointCloud<PointRadar> out;
  const double dt = 1e-6 * static_cast<double>(step.timestamp_us - previous_stamp_us);
  if (compensate && step.status != StepStatus::First && dt > 0)
    compensateMotion(scan, velocityOf(step.motion, dt), out);
  else
    out = scan;
  return out;
}

/// A matcher that merges its source itself gets the full scans; the others merged points.
double voxelFor(const ScanningRunOptions& options) {
  return findMatcher(options.matcher.method).uses.merges_source ? 0.0 : options.pcl_voxel_size;
}

/// One prepared scan into the odometry, the same for a run and a stream: matched, or bridged when
/// it could not be read.
class ScanStepper {
 public:
  ScanStepper(ScanningOdometry& odometry, const ScanningRunOptions& options) : odometry_(odometry), options_(options) {}

  /// The step `p` (stamped `stamp_us`) made, or null when it was bridged (`*problem` says why);
  /// `*problem` is also set for a step no match was made for. With `at_reference`, the scan's
  /// points at its reference time for a step that was not skipped.
  const OdometryStep* add(detail::PreparedScan& p, std::int64_t stamp_us, std::string* problem,
                          pcl::PointCloud<PointRadar>* at_reference) {
    if (!p.cloud) {
      *problem = p.problem;
      odometry_.bridge(stamp_us);
      return nullptr;
    }
    const OdometryStep& step = odometry_.addScan(ScanFrame{stamp_us, p.cloud});
    *problem = problemOf(step, options_.odometry,
                         odometry_.usesGyro() ? "the prior (constant velocity, gyro yaw)" : "constant-velocity motion");
    if (at_reference && step.status != StepStatus::Skipped)
      *at_reference = atReferenceTime(*p.cloud, step, last_stamp_us_, options_.odometry.compensation.enabled);
    if (step.status != StepStatus::Skipped) last_stamp_us_ = step.timestamp_us;
    return &step;
  }

 private:
  ScanningOdometry& odometry_;
  const ScanningRunOptions& options_;
  std::int64_t last_stamp_us_ = 0;  ///< of the last scan that was matched (or dead-reckoned)
};

}  // namespace

ScanningRunOptions defaultScanningOptions(const ScanningSequence& sequence) {
  ScanningRunOptions o;
  if (sequence.format() != ScanFormat::Boreas || sequence.size() == 0) return o;
  bool chirps = false;
  try {
    chirps = !sequence.load(0).chirp_up.empty();
  } catch (const IoError&) {
    return o;  // the run reports the unreadable scan
  }
  if (chirps) {
    o.front_end.threshold = kBoreasChirpThreshold;
    o.matcher.power_shift = kBoreasChirpThreshold;  // the paper's s equals its threshold
  }
  return o;
}

ScanningRunResult runScanningOdometry(const ScanSource& sequence, const ScanningRunOptions& options,
                                      const std::function<void(std::size_t, std::size_t)>& progress,
                                      const ScanCallback& on_scan) {
  options.validate();
  if (options.start >= sequence.size())
    throw std::invalid_argument("start scan " + std::to_string(options.start) + " is past the sequence's " +
                                std::to_string(sequence.size()) + " scans");
  const std::size_t end =
      options.max_scans > 0 ? std::min(sequence.size(), options.start + options.max_scans) : sequence.size();
  const std::size_t n = end - options.start;
  ScanningOdometry odometry(options.odometry, makeMatcher(options.matcher));
  ScanningRunResult result = startResult(sequence, options);
  if (options.odometry.gyro.enabled) attachGyro(sequence, odometry, result.problems);
  if (odometry.usesGyro()) result.prior = "constant velocity, gyro yaw";
  ScanStepper stepper(odometry, options);
  ScanSamples samples;
  const auto wall0 = Clock::now();
  // Scans are prepared on the worker threads and matched here in order, one at a time.
  detail::forEachPreparedScan(
      sequence, detail::ScanFrontEnd{options.front_end, options.chirp}, voxelFor(options), options.start, end,
      result.threads, [&](detail::PreparedScan& p) {
        const std::size_t k = p.index;
        std::string problem;
        pcl::PointCloud<PointRadar> at_reference;
        const OdometryStep* step = stepper.add(p, sequence.stamp(k), &problem, on_scan ? &at_reference : nullptr);
        if (!step) {
          result.problems.push_back("scan " + std::to_string(k) + ": " + problem + " (bridged with the motion model)");
        } else {
          if (!problem.empty())
            result.problems.push_back("scan " + std::to_string(k) + ": " + sequence.scanName(k) + ": " + problem);
          samples.add(p, *step);
          if (on_scan && step->status != StepStatus::Skipped) on_scan(k, *step, at_reference);
        }
        if (progress) progress(k - options.start + 1, n);
      });
  result.wall_s = std::chrono::duration<double>(Clock::now() - wall0).count();
  result.scans_per_second = result.wall_s > 0 ? static_cast<double>(n) / result.wall_s : 0.0;
  result.median_ms = {median(samples.read), median(samples.front_end), 0.0, median(samples.match)};
  result.median_total_ms = median(samples.total);
  result.median_points = median(samples.points);
  result.steps = odometry.steps();
  result.counters = odometry.counters();
  result.estimate = odometry.trajectory();
  result.ground_truth = rebasedGroundTruth(sequence.groundTruth(), result.estimate);
  return result;
}

struct ScanningStream::Impl {
  explicit Impl(const ScanningRunOptions& o)
      : options((o.validate(), o)),
        threshold(o.front_end),
        odometry(o.odometry, makeMatcher(o.matcher)),
        stepper(odometry, options) {}
  ScanningRunOptions options;
  PowerThreshold threshold;
  ScanningOdometry odometry;
  ScanStepper stepper;
};

ScanningStream::ScanningStream(const ScanningRunOptions& options) : impl_(std::make_unique<Impl>(options)) {}
ScanningStream::~ScanningStream() = default;

ScanningStream::Added ScanningStream::add(PolarScan scan, const std::string& name, bool want_points) {
  Added a;
  const std::int64_t stamp = scan.stamp;
  detail::PreparedScan p = detail::prepareDecodedScan(std::move(scan), name, impl_->threshold, impl_->options.chirp,
                                                      voxelFor(impl_->options));
  a.front_end_ms = p.front_end_ms;
  std::string problem;
  const OdometryStep* step = impl_->stepper.add(p, stamp, &problem, want_points ? &a.points : nullptr);
  a.step = step ? *step : impl_->odometry.steps().back();
  a.bridged = step == nullptr;
  a.published = a.step.status != StepStatus::Skipped;
  if (!problem.empty()) a.problem = step ? name + ": " + problem : problem + " (bridged with the motion model)";
  return a;
}

const ScanningOdometry& ScanningStream::odometry() const {
  return impl_->odometry;
}
void ScanningStream::setYawRate(std::shared_ptr<const TimeSeries> yaw_rate) {
  impl_->odometry.setYawRate(std::move(yaw_rate));
}

}  // namespace radar_ndt
