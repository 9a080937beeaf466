// Run reports: the steps CSV, the summary JSON (with the metrics in radar_eval's shape) and text.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <sstream>

#include <nlohmann/json.hpp>

#include "radar_ndt/evaluation/run_report.h"
#include "radar_ndt/evaluation/svg_plot.h"

using namespace radar_ndt;

namespace {
ScanningRunResult scanningRun() {
  ScanningRunResult r;
  r.sequence = "seq";
  r.method = "pcl-ndt";
  r.period_s = 0.25;
  r.scans_per_second = 40;
  for (int k = 0; k < 3; ++k) {
    OdometryStep s;
    s.timestamp_us = 1000000 + 250000 * k;
    s.status = k == 0 ? StepStatus::First : (k == 1 ? StepStatus::Matched : StepStatus::Fallback);
    s.motion = Pose2(2.5 * (k > 0), 0.01, 0.001);
    r.steps.push_back(s);
  }
  r.counters.cycles = 3;
  r.counters.matched = 1;
  r.counters.fallbacks = 1;
  r.counters.poor_fit = 1;
  r.problems = {"scan 7: broken"};
  return r;
}
}  // namespace

TEST(RunReport, StepsCsvHasAHeaderAndOneLinePerStep) {
  const std::string csv = stepsCsv(scanningRun());
  std::istringstream in(csv);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("timestamp_us,status,attempts,grid,power_shift", 0), 0u) << header;
  int lines = 0;
  while (std::getline(in, line)) ++lines;
  EXPECT_EQ(lines, 3);
  EXPECT_NE(csv.find("1500000,fallback,"), std::string::npos) << csv;

  AutomotiveRunResult a;
  a.steps.resize(2);
  a.steps[1].timestamp_us = 75000;
  a.ground_truth.stamps = {0.0, 0.075};
  a.ground_truth.poses = {toIsometry3(Pose2::Zero()), toIsometry3(Pose2(0.8, 0.0, 0.0))};
  a.steps[1].match_motion = Pose2(0.79, 0.01, 0.002);
  a.steps[1].yaw_rate_bias = 0.003;
  const std::string acsv = stepsCsv(a);
  EXPECT_NE(
      acsv.find(
          ",gt_dx,gt_dy,gt_dyaw,match_dx,match_dy,match_dyaw,match_var_x,match_var_y,match_var_yaw,yaw_rate_bias\n"),
      std::string::npos);
  EXPECT_NE(acsv.find(",0.8,0,0,0.79,0.01,0.002,nan,nan,nan,0.003\n"), std::string::npos)
      << "the ground-truth motion, the raw match, its (absent) covariance and the bias of the cycle: " << acsv;
}

TEST(RunReport, SummaryJsonCarriesTheCountsAndTheMetricsInTheSharedShape) {
  const ScanningRunResult r = scanningRun();
  nlohmann::json j = nlohmann::json::parse(summaryJson(r));
  EXPECT_EQ(j["method"], "pcl-ndt");
  EXPECT_EQ(j["scans"], 3);
  EXPECT_EQ(j["fallbacks"], 1);
  EXPECT_DOUBLE_EQ(j["fallback_rate"].get<double>(), 1.0 / 3.0);
  EXPECT_EQ(j["attempts_rejected_for_poor_fit"], 1);
  EXPECT_EQ(j["problems"], 1);
  EXPECT_DOUBLE_EQ(j["real_time_factor"].get<double>(), 10.0);
  EXPECT_FALSE(j.contains("metrics"));
  EvaluationReport rep;
  rep.frame = FrameError{0.05, 0.1, 2};
  j = nlohmann::json::parse(summaryJson(r, &rep));
  EXPECT_DOUBLE_EQ(j["metrics"]["frame"]["trans_err_m"].get<double>(), 0.05);
  EXPECT_EQ(j["metrics"], nlohmann::json::parse(metricsJson(rep)));

  AutomotiveRunResult a;
  a.scene = "scene-1";
  a.method = "doppler";
  a.submap_size = 3;
  a.period_s = 0.075;
  a.median_total_ms = 0.75;
  const nlohmann::json aj = nlohmann::json::parse(summaryJson(a));
  EXPECT_EQ(aj["method"], "doppler");
  EXPECT_EQ(aj["submap"], 3);
  EXPECT_DOUBLE_EQ(aj["real_time_factor"].get<double>(), 100.0);
  EXPECT_NE(summaryText(a).find("scene-1: 0 cycles"), std::string::npos) << summaryText(a);
  EXPECT_NE(summaryText(r).find("fallbacks 1 (33.3 %)"), std::string::npos) << summaryText(r);
}

// The text summary counts every step once (they add up to the steps), and a run whose steps were
// mostly not matched gets a failure line that says how; a matched run gets none.
TEST(RunReport, TheSummaryAccountsForEveryStepAndAFailedRunSaysSo) {
  ScanningRunResult r;
  r.sequence = "seq";
  StepLog log;
  auto add = [&](std::int64_t t, StepStatus status, bool too_few) {
    OdometryStep s = log.begin(t);
    s.status = status;
    s.too_few_points = too_few;
    log.add(s);
  };
  add(0, StepStatus::First, false);
  for (int k = 1; k <= 6; ++k) add(k, StepStatus::Matched, false);
  add(7, StepStatus::Fallback, false);
  log.bridge(8, ConstantVelocityModel());
  r.counters = log.counters();
  EXPECT_NE(summaryText(r).find("9 scans"), std::string::npos) << summaryText(r);
  EXPECT_NE(summaryText(r).find("first 1, matched 6, retried 0, fallbacks 1 (11.1 %), dead-reckoned 0 (0 for too few "
                                "points), bridged 1, skipped 0"),
            std::string::npos)
      << summaryText(r);
  EXPECT_EQ(failureText(r), "") << "2 of 8 not matched";
  for (int k = 9; k <= 14; ++k) add(k, StepStatus::DeadReckoned, true);
  r.counters = log.counters();
  const std::string failure = failureText(r);
  EXPECT_EQ(failure.rfind("seq: FAILED: 8 of the 14 scans after the first were not matched (6 too few points, 1 "
                          "fallbacks, 1 unreadable)",
                          0),
            0u)
      << failure;
  EXPECT_EQ(failure.back(), '\n');
  const nlohmann::json j = nlohmann::json::parse(summaryJson(r));
  EXPECT_EQ(j["too_few_points"], 6);
  EXPECT_EQ(j["unmatched"], 8);
  EXPECT_EQ(j["mostly_unmatched"], true);
  // An automotive run without a matcher (the Doppler integral) dead-reckons by design: not a failure.
  AutomotiveRunResult a;
  a.scene = "scene-1";
  StepLog doppler;
  for (int k = 0; k < 10; ++k) {
    OdometryStep s = doppler.begin(k);
    s.status = k == 0 ? StepStatus::First : StepStatus::DeadReckoned;
    doppler.add(s);
  }
  a.counters = doppler.counters();
  EXPECT_EQ(failureText(a), "");
}

TEST(RunReport, ThePriorIsJudgedAgainstTheTruthAsTheMatchesAre) {
  // The truth: 1 m a step along x, 0.01 rad a step; each step's guess 1.1 m and 0.03 rad, its
  // match exact. A skipped step has no pose and is left out; the first has no motion.
  Trajectory gt;
  for (int k = 0; k < 6; ++k) {
    gt.stamps.push_back(0.25 * k);
    gt.poses.push_back(toIsometry3(Pose2(1.0 * k, 0.0, 0.01 * k)));
  }
  std::vector<OdometryStep> steps;
  for (int k = 0; k < 6; ++k) {
    OdometryStep s;
    s.timestamp_us = 250000 * k;
    s.status = k == 0 ? StepStatus::First : StepStatus::Matched;
    const Pose2 truth = between(Pose2(1.0 * (k - 1), 0.0, 0.01 * (k - 1)), Pose2(1.0 * k, 0.0, 0.01 * k));
    s.motion = truth;
    s.prior_motion = truth + Pose2(0.1, 0.0, 0.02);
    steps.push_back(s);
  }
  OdometryStep skipped = steps[3];
  skipped.status = StepStatus::Skipped;
  skipped.prior_motion = Pose2(50.0, 0.0, 1.0);  // would dominate the mean if counted
  steps.insert(steps.begin() + 4, skipped);
  const FrameError prior = priorFrameError(steps, gt);
  EXPECT_EQ(prior.pairs, 5u);
  EXPECT_NEAR(prior.rot_err_deg, 0.02 * 180.0 / kPi, 1e-9);
  EXPECT_NEAR(prior.trans_err_m, 0.1, 2e-3);  // the guess's extra 0.1 m, seen from the turned frame
  EXPECT_NE(priorText(prior, "constant velocity").find("prior (constant velocity): frame 0.1"), std::string::npos);
  EXPECT_EQ(priorText(FrameError{}, "constant velocity"), "");
}

// A run judged against its ground truth once, for every caller (evaluateRun): the metrics, and the
// method's own prior beside them, named as the run names it; the SVG of estimate against truth.
TEST(RunReport, ARunsEvaluationCarriesItsPriorUnderItsOwnName) {
  ScanningRunResult r = scanningRun();
  r.prior = "constant velocity, gyro yaw";
  Pose2 pose = Pose2::Zero();
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    OdometryStep& s = r.steps[k];
    s.prior_motion = Pose2(2.4, 0.0, 0.0);
    if (k > 0) pose = compose(pose, s.motion);
    s.pose = pose;
    r.estimate.stamps.push_back(1e-6 * static_cast<double>(s.timestamp_us));
    r.estimate.poses.push_back(toIsometry3(pose));
    r.ground_truth.stamps.push_back(1e-6 * static_cast<double>(s.timestamp_us));
    r.ground_truth.poses.push_back(toIsometry3(Pose2(2.5 * static_cast<double>(k), 0.0, 0.0)));
  }
  const RunEvaluation e = evaluateRun(r, {Metric::Frame});
  EXPECT_EQ(e.prior_label, "constant velocity, gyro yaw");
  EXPECT_EQ(e.prior.pairs, 2u);
  EXPECT_NEAR(e.prior.trans_err_m, 0.1, 1e-9);
  const nlohmann::json j = nlohmann::json::parse(summaryJson(r, e));
  EXPECT_EQ(j["prior_frame"]["prior"], "constant velocity, gyro yaw");
  EXPECT_TRUE(j.contains("metrics"));
  const std::string text = evaluationText(e);
  EXPECT_NE(text.find("prior (constant velocity, gyro yaw)"), std::string::npos) << text;
  const std::string svg = ::testing::TempDir() + "run_report_eval.svg";
  writeEvaluationSvg(svg, associate(r.ground_truth, r.estimate), e.report, "seq");
  std::ifstream in(svg);
  const std::string whole((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(whole.find("<svg"), std::string::npos);
  EXPECT_NE(whole.find("</svg>"), std::string::npos);
}

TEST(RunReport, ASixDofEvaluationsPlotHasItsSideViewAndAPlanarOneHasNone) {
  // A ramp: 2 m forward and 0.5 m up a pose on the truth, the estimate 0.25 m a pose too low.
  Trajectory gt, est;
  for (int k = 0; k < 20; ++k) {
    Eigen::Isometry3d g = Eigen::Isometry3d::Identity();
    g.translation() = Eigen::Vector3d(2.0 * k, 0, 0.5 * k);
    Eigen::Isometry3d e = g;
    e.translation().z() -= 0.25 * k;
    gt.stamps.push_back(0.1 * k);
    est.stamps.push_back(0.1 * k);
    gt.poses.push_back(g);
    est.poses.push_back(e);
  }
  const PosePairs pairs = associate(gt, est);
  const auto read = [](const std::string& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const std::string six = ::testing::TempDir() + "run_report_6dof.svg";
  writeEvaluationSvg(six, pairs, evaluate(pairs, {Metric::Ate6Dof, Metric::Frame}), "walk");
  const std::string s = read(six);
  EXPECT_NE(s.find("height='900'"), std::string::npos);
  EXPECT_NE(s.find("distance travelled (m)"), std::string::npos);
  EXPECT_NE(s.find("height z (m)"), std::string::npos);
  const std::string planar = ::testing::TempDir() + "run_report_planar.svg";
  writeEvaluationSvg(planar, pairs, evaluate(pairs, {Metric::Frame}), "drive");
  const std::string p = read(planar);
  EXPECT_NE(p.find("height='600'"), std::string::npos);
  EXPECT_EQ(p.find("height z"), std::string::npos);
}
