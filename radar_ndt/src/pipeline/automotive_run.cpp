#include "radar_ndt/pipeline/automotive_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "detail/run_timing.h"

namespace radar_ndt {

using detail::Clock;
using detail::median;
namespace {
double ms(Clock::time_point a, Clock::time_point b) {
  return detail::msBetween(a, b);
}
}  // namespace

void AutomotiveRunOptions::validate() const {
  matcher.validate();
  sequence.validate();
  front_end.validate();
  odometry.validate();
}

AutomotiveRunOptions withMethod(AutomotiveRunOptions options, Method method) {
  options.matcher.method = method;
  options.odometry.doppler_weights = method == Method::RappNdt;
  if (method == Method::RappNdt) options.front_end.remove_moving = false;
  // The fusion's match covariance per matcher, calibrated on the shared nuScenes scenes
  // (radar_paper_tables --noise-calibration; docs/automotive_pipeline.md): ours reports one, which
  // Rapp's weights make less optimistic; PCL's matchers report none.
  MotionFusionOptions& f = options.odometry.fusion;
  if (method == Method::RappNdt) f.match_covariance_scale = 1.23;
  if (method == Method::PclNdt) {
    f.match_sigma_x = 0.040;
    f.match_sigma_y = 0.046;
    f.match_sigma_yaw = 0.0017;
  }
  if (method == Method::PclIcp) {
    f.match_sigma_x = 0.074;
    f.match_sigma_y = 0.071;
    f.match_sigma_yaw = 0.0021;
  }
  return options;
}

AutomotiveRunResult runAutomotiveOdometry(const NuScenesDataset& dataset, const NuScenesScene& scene,
                                          const AutomotiveRunOptions& options,
                                          const std::function<void(std::size_t, std::size_t)>& progress) {
  options.validate();
  return runAutomotiveOdometry(dataset, scene, options, makeMatcher(options.matcher, options.odometry.grid), progress);
}

AutomotiveRunResult runAutomotiveOdometry(const NuScenesDataset& dataset, const NuScenesScene& scene,
                                          const AutomotiveRunOptions& options, MatcherAdapter matcher,
                                          const std::function<void(std::size_t, std::size_t)>& progress) {
  options.validate();
  const NuScenesRadarSequence sequence(dataset, scene, options.sequence);
  const AutomotiveFrontEnd front_end(options.front_end);
  if (matcher) matcher.setGrid(options.odometry.grid);
  AutomotiveOdometry odometry(options.odometry, std::move(matcher));

  AutomotiveRunResult result;
  result.scene = scene.name;
  result.method = options.matcher.method;
  result.submap_size = options.odometry.submap_size;
  result.reference_channel = sequence.referenceChannel();
  result.period_s = sequence.periodSeconds();
  result.problems = sequence.silences();
  const std::size_t n = options.max_cycles > 0 ? std::min(options.max_cycles, sequence.size()) : sequence.size();
  std::vector<double> read, fe, sub, match, total, residual;
  EgoVelocity last_valid;
  bool have_valid = false;
  for (std::size_t k = 0; k < n; ++k) {
    const auto t0 = Clock::now();
    std::vector<std::string> problems;
    const RadarCycle cycle = sequence.load(k, &problems);
    const auto t1 = Clock::now();
    const ProcessedCycle processed = front_end.process(cycle, have_valid ? &last_valid : nullptr);
    const auto t2 = Clock::now();
    result.detections += processed.raw_points;
    result.removed_moving += processed.removed_moving;
    if (processed.ego.valid) {
      residual.push_back(processed.ego.residual_rms);
      if (processed.ego.nonholonomic) ++result.nonholonomic_velocity_cycles;
      last_valid = processed.ego;
      have_valid = true;
    } else {
      ++result.invalid_velocity_cycles;
    }
    result.ego_speed.push_back(processed.ego.valid ? processed.ego.velocity.head<2>().norm()
                                                   : std::numeric_limits<double>::quiet_NaN());
    const OdometryStep& step = odometry.add(processed);
    for (const auto& p : problems) result.problems.push_back("cycle " + std::to_string(k) + ": " + p);
    read.push_back(ms(t0, t1));
    fe.push_back(ms(t1, t2));
    sub.push_back(step.submap_ms);
    match.push_back(step.match_ms);
    total.push_back(read.back() + fe.back() + sub.back() + match.back());
    if (progress) progress(k + 1, n);
  }
  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / static_cast<double>(v.size());
  };
  result.median_ms = {median(read), median(fe), median(sub), median(match)};
  result.mean_ms = {mean(read), mean(fe), mean(sub), mean(match)};
  result.median_total_ms = median(total);
  result.median_doppler_residual = median(residual);
  result.steps = odometry.steps();
  result.counters = odometry.counters();
  result.estimate = odometry.trajectory();
  const Trajectory gt = sequence.groundTruthTrajectory();
  result.ground_truth.stamps.assign(gt.stamps.begin(), gt.stamps.begin() + static_cast<std::ptrdiff_t>(n));
  result.ground_truth.poses.assign(gt.poses.begin(), gt.poses.begin() + static_cast<std::ptrdiff_t>(n));
  return result;
}

}  // namespace radar_ndt
