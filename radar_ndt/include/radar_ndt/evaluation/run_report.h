#pragma once
// Reports of one odometry run, the same for every app and for library users: one CSV line per
// step, the run's summary as JSON (with the metrics in radar_eval's shape when evaluated) and as
// readable text.

#include <string>
#include <vector>

#include "radar_ndt/evaluation/report.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/inertial_run.h"
#include "radar_ndt/pipeline/scanning_run.h"

namespace radar_ndt {

/// The metrics each pipeline reports when none are asked for: the paper's 1 m metric for the
/// automotive pipeline, KITTI and frame-to-frame errors for the scanning one.
inline std::vector<Metric> defaultMetrics(const AutomotiveRunResult&) {
  return {Metric::OneMeter};
}
inline std::vector<Metric> defaultMetrics(const ScanningRunResult&) {
  return {Metric::Kitti, Metric::Frame};
}

/// The 6-DoF pipeline: rpg's ATE (both alignments), relative error and the final position error.
inline std::vector<Metric> defaultMetrics(const InertialRunResult&) {
  return {Metric::Ate6Dof, Metric::Relative, Metric::Final};
}

/// One CSV line per cycle after a header: timestamp_us, status, attempts, grid, chi2, the matched
/// motion, the Doppler motion, point counts, velocity_valid and the ground-truth motion.
std::string stepsCsv(const AutomotiveRunResult& run);
/// One CSV line per scan after a header: timestamp_us, status, attempts, grid, power_shift,
/// compensation_rounds, slow, the matched motion, the constant-velocity guess, point counts, match_ms.
std::string stepsCsv(const ScanningRunResult& run);

/// The run's summary as a JSON object (indented by 2): counts, failure handling, timings, and
/// with `metrics` a "metrics" entry shaped as metricsJson's.
std::string summaryJson(const AutomotiveRunResult& run, const EvaluationReport* metrics = nullptr);
std::string summaryJson(const ScanningRunResult& run, const EvaluationReport* metrics = nullptr);
/// The 6-DoF run's: one CSV line per scan (stamp, pose as TUM's x y z qx qy qz qw, the Doppler body
/// velocity, what the step did, points, iterations, match_ms, why); its summary with the method,
/// whether the IMU was fused, the prior, counts and ms per scan.
std::string stepsCsv(const InertialRunResult& run);
std::string summaryJson(const InertialRunResult& run, const EvaluationReport* metrics = nullptr);

/// The method's own prior, judged as the matches are: the mean frame error of each step's initial
/// guess (scanning: constant velocity; nuScenes: the Doppler ego-motion) against the ground-truth
/// motion between that step and the one before it (steps with a pose, both inside the ground
/// truth). What a matcher that returned its guess would score on the frame metric.
FrameError priorFrameError(const std::vector<OdometryStep>& steps, const Trajectory& ground_truth);
/// One line for the apps: "prior (constant velocity): frame X m Y deg over N pairs" (the label
/// says which prior), "" without pairs.
std::string priorText(const FrameError& prior, const char* label);

/// A run judged against its ground truth, the same for every caller: its metrics and, beside them,
/// its own prior's frame error, the prior named as the run names it (run.prior).
struct RunEvaluation {
  EvaluationReport report;
  FrameError prior;
  std::string prior_label;
};
/// `metrics` empty: the pipeline's (defaultMetrics). std::invalid_argument from evaluate() when the
/// run and its ground truth share too few poses.
RunEvaluation evaluateRun(const AutomotiveRunResult& run, const std::vector<Metric>& metrics = {});
RunEvaluation evaluateRun(const ScanningRunResult& run, const std::vector<Metric>& metrics = {});
/// The 6-DoF run: its metrics alone (its honest baseline is the doppler-imu method's own run).
RunEvaluation evaluateRun(const InertialRunResult& run, const std::vector<Metric>& metrics = {});
/// The summary JSON with the evaluation: "metrics" (metricsJson's shape) and, where the prior was
/// judged, "prior_frame" {prior, trans_err_m, rot_err_deg, pairs}.
std::string summaryJson(const AutomotiveRunResult& run, const RunEvaluation& evaluation);
std::string summaryJson(const ScanningRunResult& run, const RunEvaluation& evaluation);
std::string summaryJson(const InertialRunResult& run, const RunEvaluation& evaluation);
/// The metrics table and the prior's line, as the apps print them after the summary.
std::string evaluationText(const RunEvaluation& evaluation);

/// For a run whose steps were mostly not matched (OdometryCounters::mostlyUnmatched: fallbacks,
/// too few points and unreadable files, more than half of the steps after the first), one line
/// that says so, how, and what to check; "" otherwise. radar_odometry prints it last and exits 1.
std::string failureText(const AutomotiveRunResult& run);
std::string failureText(const ScanningRunResult& run);
/// 6-DoF: fallbacks and unreadable scans more than half of the scans after the first.
std::string failureText(const InertialRunResult& run);

/// The summary as the apps print it (a few lines: every step counted once, first, matched,
/// retried, fallbacks, dead-reckoned, bridged and skipped adding up to the steps), without the
/// metrics table.
std::string summaryText(const AutomotiveRunResult& run);
std::string summaryText(const ScanningRunResult& run);
std::string summaryText(const InertialRunResult& run);

/// Real-time factor of a run: how many times faster than the sensor it processes (one core for
/// the automotive pipeline; end to end, with the prefetch thread, for the scanning one).
double realTimeFactor(const AutomotiveRunResult& run);
double realTimeFactor(const ScanningRunResult& run);
/// 6-DoF: the recording's duration over the run's wall time (one thread, reading included).
double realTimeFactor(const InertialRunResult& run);

}  // namespace radar_ndt
