#include "radar_ndt/evaluation/run_report.h"

#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "detail/printf_string.h"

namespace radar_ndt {

using nlohmann::json;

namespace {

double percent(std::size_t part, std::size_t whole) {
  return whole ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0;
}

using detail::format;

/// The step counts both pipelines report.
void addStepCounts(json& j, const OdometryCounters& c) {
  j["first"] = c.first;
  j["matched"] = c.matched;
  j["retried"] = c.retried;
  j["fallbacks"] = c.fallbacks;
  j["fallback_rate"] = c.cycles ? static_cast<double>(c.fallbacks) / static_cast<double>(c.cycles) : 0.0;
  j["dead_reckoned"] = c.dead_reckoned;
  j["too_few_points"] = c.too_few_points;
  j["skipped"] = c.skipped;
  j["bridged"] = c.bridged;
  j["unmatched"] = c.unmatched();
  j["mostly_unmatched"] = c.mostlyUnmatched();
}

/// Every step counted once: first, matched, retried, fallbacks, dead-reckoned, bridged, skipped
/// (they add up to the steps).
std::string stepCounts(const OdometryCounters& c) {
  return format(
      "first %zu, matched %zu, retried %zu, fallbacks %zu (%.1f %%), dead-reckoned %zu (%zu for too few points), "
      "bridged %zu, skipped %zu",
      c.first, c.matched, c.retried, c.fallbacks, percent(c.fallbacks, c.cycles), c.dead_reckoned, c.too_few_points,
      c.bridged, c.skipped);
}

/// The verdict on a run whose steps were mostly not matched; "" for the others.
std::string failureLine(const std::string& name, const OdometryCounters& c, const char* unit, const char* advice) {
  if (!c.mostlyUnmatched()) return "";
  return format(
      "%s: FAILED: %zu of the %zu %s after the first were not matched (%zu too few points, %zu fallbacks, %zu "
      "unreadable): the trajectory is mostly dead reckoning, not odometry; %s\n",
      name.c_str(), c.unmatched(), c.matchable(), unit, c.too_few_points, c.fallbacks, c.bridged, advice);
}

}  // namespace

std::string failureText(const AutomotiveRunResult& r) {
  return failureLine(r.scene, r.counters, "cycles", "check the radars' data and the front-end's filters");
}
std::string failureText(const ScanningRunResult& r) {
  return failureLine(r.sequence, r.counters, "scans",
                     "a front-end that leaves too few points (--threshold for another sensor?) or no usable scans");
}

double realTimeFactor(const AutomotiveRunResult& r) {
  return r.median_total_ms > 0 ? 1000.0 * r.period_s / r.median_total_ms : 0.0;
}
std::string threadsText(int threads) {
  return threads == 1 ? "one thread" : std::to_string(threads) + " threads";
}
double realTimeFactor(const ScanningRunResult& r) {
  return r.period_s > 0 ? r.scans_per_second * r.period_s : 0.0;
}

std::string stepsCsv(const AutomotiveRunResult& r) {
  std::ostringstream csv;
  csv << "timestamp_us,status,attempts,grid,chi2,dx,dy,dyaw,doppler_dx,doppler_dy,doppler_dyaw,source_points,target_"
         "points,"
         "velocity_valid,gt_dx,gt_dy,gt_dyaw,match_dx,match_dy,match_dyaw,match_var_x,match_var_y,match_var_yaw,yaw_"
         "rate_bias\n";
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    const OdometryStep& s = r.steps[k];
    const Pose2 gt = k > 0 && k < r.ground_truth.size()
                         ? between(toPose2(r.ground_truth.poses[k - 1]), toPose2(r.ground_truth.poses[k]))
                         : Pose2::Zero();
    csv << s.timestamp_us << ',' << toString(s.status) << ',' << s.attempts << ',' << s.grid << ',' << s.chi2 << ','
        << s.motion.x() << ',' << s.motion.y() << ',' << s.motion.z() << ',' << s.prior_motion.x() << ','
        << s.prior_motion.y() << ',' << s.prior_motion.z() << ',' << s.source_points << ',' << s.target_points << ','
        << s.velocity_valid << ',' << gt.x() << ',' << gt.y() << ',' << gt.z() << ',' << s.match_motion.x() << ','
        << s.match_motion.y() << ',' << s.match_motion.z() << ',' << s.match_covariance(0, 0) << ','
        << s.match_covariance(1, 1) << ',' << s.match_covariance(2, 2) << ',' << s.yaw_rate_bias << '\n';
  }
  return csv.str();
}

std::string stepsCsv(const ScanningRunResult& r) {
  std::ostringstream csv;
  csv << "timestamp_us,status,attempts,grid,power_shift,compensation_rounds,slow,dx,dy,dyaw,guess_dx,guess_dy,guess_"
         "dyaw,"
         "source_points,target_points,match_ms,keyframe\n";
  for (const OdometryStep& s : r.steps)
    csv << s.timestamp_us << ',' << toString(s.status) << ',' << s.attempts << ',' << s.grid << ',' << s.power_shift
        << ',' << s.compensation_rounds << ',' << s.slow << ',' << s.motion.x() << ',' << s.motion.y() << ','
        << s.motion.z() << ',' << s.prior_motion.x() << ',' << s.prior_motion.y() << ',' << s.prior_motion.z() << ','
        << s.source_points << ',' << s.target_points << ',' << s.match_ms << ',' << s.keyframe << '\n';
  return csv.str();
}

std::string summaryJson(const AutomotiveRunResult& r, const EvaluationReport* metrics) {
  const auto& c = r.counters;
  json j;
  j["scene"] = r.scene;
  j["method"] = r.method;
  j["submap"] = r.submap_size;
  j["reference_channel"] = r.reference_channel;
  j["cycles"] = c.cycles;
  j["cycle_period_s"] = r.period_s;
  addStepCounts(j, c);
  j["invalid_velocity_cycles"] = r.invalid_velocity_cycles;
  j["nonholonomic_velocity_cycles"] = r.nonholonomic_velocity_cycles;
  // Only when it happens: a radar on the rear axle's line is rare, and every other run's report
  // keeps its keys.
  if (r.forward_speed_cycles > 0) j["forward_speed_cycles"] = r.forward_speed_cycles;
  j["problems"] = r.problems.size();  // radars gone silent, unreadable sweeps
  j["detections"] = r.detections;
  j["removed_moving"] = r.removed_moving;
  j["median_doppler_residual_mps"] = r.median_doppler_residual;
  j["ms_per_cycle_median"] = {{"read", r.median_ms.read_ms},
                              {"front_end", r.median_ms.front_end_ms},
                              {"submap", r.median_ms.submap_ms},
                              {"match", r.median_ms.match_ms},
                              {"total", r.median_total_ms}};
  j["real_time_factor"] = realTimeFactor(r);
  if (metrics) j["metrics"] = json::parse(metricsJson(*metrics));
  return j.dump(2);
}

std::string summaryJson(const ScanningRunResult& r, const EvaluationReport* metrics) {
  const auto& c = r.counters;
  json j;
  j["sequence"] = r.sequence;
  j["format"] = r.format;
  j["method"] = r.method;
  j["scans"] = c.cycles;
  j["scan_period_s"] = r.period_s;
  addStepCounts(j, c);
  j["power_shift_halved"] = c.shift_halved;
  j["slow_grid"] = c.slow;
  j["attempts_not_converged"] = c.not_converged;
  j["attempts_rejected_by_motion_prior"] = c.rejected;
  j["attempts_rejected_for_poor_fit"] = c.poor_fit;
  j["unreadable_files"] = c.bridged;  // scans that could not be read or had no noise floor
  j["problems"] = r.problems.size();  // those, bad index lines and steps no match passed for
  j["points_per_scan_median"] = r.median_points;
  j["ms_per_scan_median"] = {{"decode", r.median_ms.read_ms},
                             {"front_end", r.median_ms.front_end_ms},
                             {"match", r.median_ms.match_ms},
                             {"total", r.median_total_ms}};
  j["scans_per_second"] = r.scans_per_second;
  j["real_time_factor"] = realTimeFactor(r);
  if (metrics) j["metrics"] = json::parse(metricsJson(*metrics));
  return j.dump(2);
}

std::string summaryText(const AutomotiveRunResult& r) {
  const auto& c = r.counters;
  std::string s = format(
      "%s: %zu cycles (reference %s, %.1f Hz): %s; %zu problems (unreadable sweeps, silent "
      "radars, cycles with too few points)\n",
      r.scene.c_str(), c.cycles, r.reference_channel.c_str(), r.period_s > 0 ? 1.0 / r.period_s : 0.0,
      stepCounts(c).c_str(), r.problems.size());
  s += format(
      "  %zu detections, %.1f %% removed as moving; Doppler fit residual %.3f m/s (median), %zu cycles without a valid "
      "ego-velocity\n",
      r.detections, percent(r.removed_moving, r.detections), r.median_doppler_residual, r.invalid_velocity_cycles);
  const std::size_t with_rate = r.nonholonomic_velocity_cycles - r.forward_speed_cycles;
  if (with_rate > 0)
    s +=
        format("  ego-velocity with vy = 0 (radars at one place: yaw rate from the single-radar model) in %zu cycles\n",
               with_rate);
  if (r.forward_speed_cycles > 0)
    s += format(
        "  ego-velocity with vy = 0 and the forward speed alone (radars on the rear axle's line: the yaw rate left to "
        "the match) in %zu cycles\n",
        r.forward_speed_cycles);
  s += format(
      "  ms per cycle (median): read %.2f, front-end %.2f, submap %.2f, match %.2f, total %.2f (%.0fx real time)\n",
      r.median_ms.read_ms, r.median_ms.front_end_ms, r.median_ms.submap_ms, r.median_ms.match_ms, r.median_total_ms,
      realTimeFactor(r));
  return s;
}

std::string summaryText(const ScanningRunResult& r) {
  const auto& c = r.counters;
  std::string s = format(
      "%s: %zu scans (%s, %.2f Hz), %.0f points/scan: %s; s halved %zu, slow grid %zu; %zu "
      "problems\n",
      r.sequence.c_str(), c.cycles, r.format.c_str(), r.period_s > 0 ? 1.0 / r.period_s : 0.0, r.median_points,
      stepCounts(c).c_str(), c.shift_halved, c.slow, r.problems.size());
  s += format(
      "  ms per scan (median, one core): decode %.2f, front-end %.2f, match %.2f, total %.2f; end to end %.1f scans/s "
      "(%s), %.0fx real time\n",
      r.median_ms.read_ms, r.median_ms.front_end_ms, r.median_ms.match_ms, r.median_total_ms, r.scans_per_second,
      threadsText(r.threads).c_str(), realTimeFactor(r));
  return s;
}

FrameError priorFrameError(const std::vector<OdometryStep>& steps, const Trajectory& gt) {
  FrameError out;
  double st = 0, sr = 0;
  const OdometryStep* previous = nullptr;
  Eigen::Isometry3d previous_gt;
  for (const OdometryStep& s : steps) {
    if (s.status == StepStatus::Skipped) continue;
    Eigen::Isometry3d here;
    const bool covered = gt.poseAt(1e-6 * static_cast<double>(s.timestamp_us), &here);
    if (covered && previous != nullptr && s.status != StepStatus::First) {
      // As frameError: E = guess⁻¹ · truth, its translation norm and rotation angle.
      const Eigen::Isometry3d E = toIsometry3(s.prior_motion).inverse() * (previous_gt.inverse() * here);
      st += E.translation().norm();
      sr += rotationAngle(E.linear());
      ++out.pairs;
    }
    previous = covered ? &s : nullptr;
    previous_gt = here;
  }
  if (out.pairs > 0) {
    out.trans_err_m = st / static_cast<double>(out.pairs);
    out.rot_err_deg = sr * 180.0 / kPi / static_cast<double>(out.pairs);
  }
  return out;
}

std::string priorText(const FrameError& prior, const char* label) {
  if (prior.pairs == 0) return "";
  char line[160];
  std::snprintf(line, sizeof line, "prior (%s): frame %.5f m %.5f deg over %zu pairs\n", label, prior.trans_err_m,
                prior.rot_err_deg, prior.pairs);
  return line;
}

namespace {

template <typename Run>
RunEvaluation evaluateRunOf(const Run& run, const std::vector<Metric>& metrics) {
  RunEvaluation e;
  e.report = evaluate(associate(run.ground_truth, run.estimate), metrics.empty() ? defaultMetrics(run) : metrics);
  e.prior = priorFrameError(run.steps, run.ground_truth);
  e.prior_label = run.prior;
  return e;
}

std::string withPrior(const std::string& summary, const RunEvaluation& e) {
  if (e.prior.pairs == 0) return summary;
  json j = json::parse(summary);
  j["prior_frame"] = {{"prior", e.prior_label},
                      {"trans_err_m", e.prior.trans_err_m},
                      {"rot_err_deg", e.prior.rot_err_deg},
                      {"pairs", e.prior.pairs}};
  return j.dump(2);
}

}  // namespace

RunEvaluation evaluateRun(const AutomotiveRunResult& run, const std::vector<Metric>& metrics) {
  return evaluateRunOf(run, metrics);
}
RunEvaluation evaluateRun(const ScanningRunResult& run, const std::vector<Metric>& metrics) {
  return evaluateRunOf(run, metrics);
}

std::string summaryJson(const AutomotiveRunResult& run, const RunEvaluation& evaluation) {
  return withPrior(summaryJson(run, &evaluation.report), evaluation);
}
std::string summaryJson(const ScanningRunResult& run, const RunEvaluation& evaluation) {
  return withPrior(summaryJson(run, &evaluation.report), evaluation);
}

std::string evaluationText(const RunEvaluation& evaluation) {
  return formatTable(evaluation.report) + priorText(evaluation.prior, evaluation.prior_label.c_str());
}

}  // namespace radar_ndt
