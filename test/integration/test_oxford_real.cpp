// Real Oxford Radar RobotCar scans (../shared/data/oxford-radar-real, skipped without it): the
// reader on the dataset's own files, and the scanning pipeline's motions against the dataset's
// ground truth, associated by the scans' radar timestamps: ours, PCL's NDT and ICP, and the
// constant-velocity guesses the odometry starts from, with bounds a broken front-end, a wrong
// azimuth convention or a matcher that returns its guess would fail.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "radar_ndt/evaluation/metrics.h"
#include "radar_ndt/evaluation/report.h"
#include "radar_ndt/io/oxford_ground_truth.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/scanning_sequence.h"
#include "radar_ndt/pipeline/scanning_run.h"

using namespace radar_ndt;

namespace {

const std::string kDir = std::string(RADAR_NDT_SHARED_DATA) + "/oxford-radar-real";

bool haveData() {
  return std::filesystem::exists(kDir + "/radar.timestamps");
}

/// The dataset's motions (its radar odometry, in Oxford's axes x forward, y right), keyed by the
/// later scan's radar timestamp, in this project's axes (x forward, y left): (x, −y, −yaw).
std::map<std::int64_t, Pose2> truthByRadarStamp() {
  std::map<std::int64_t, Pose2> m;
  for (const auto& r : readOxfordRadarOdometry(kDir + "/gt/radar_odometry.csv"))
    m[r.source_radar] = Pose2(r.x, -r.y, -r.yaw);
  return m;
}

struct FrameErrors {
  double trans = 0, rot_deg = 0, mean_lateral = 0;
  std::size_t n = 0;
};

/// Mean frame errors of each step's motion (or, with `guesses`, its initial guess) against the truth.
FrameErrors frameErrors(const ScanningRunResult& r, bool guesses) {
  const auto truth = truthByRadarStamp();
  FrameErrors e;
  for (const auto& s : r.steps) {
    if (s.status == StepStatus::First) continue;
    const auto it = truth.find(s.timestamp_us);
    if (it == truth.end()) continue;
    Pose2 d = (guesses ? s.prior_motion : s.motion) - it->second;
    d.z() = normalizeAngle(d.z());
    e.trans += std::hypot(d.x(), d.y());
    e.rot_deg += std::abs(d.z()) * 180.0 / kPi;
    e.mean_lateral += d.y();
    ++e.n;
  }
  if (e.n) e.trans /= e.n, e.rot_deg /= e.n, e.mean_lateral /= e.n;
  return e;
}

ScanningRunResult run(const std::string& method) {
  ScanningRunOptions o;
  o.matcher.method = method;
  const ScanningSequence seq(kDir, ScanFormat::Oxford, o.sequence);
  return runScanningOdometry(seq, o);
}

}  // namespace

TEST(OxfordReal, ReaderOnTheDatasetsOwnFiles) {
  if (!haveData()) GTEST_SKIP() << "no " << kDir << ": skipping the real-data check";
  const std::vector<OxfordStamp> stamps = readOxfordTimestamps(kDir + "/radar.timestamps");
  ASSERT_EQ(stamps.size(), 11u);
  for (const auto& s : stamps) {
    const PolarScan scan = readOxfordPolarPng(kDir + "/radar/" + std::to_string(s.stamp) + ".png");
    ASSERT_EQ(scan.azimuths, 400);
    EXPECT_EQ(scan.bins, 3768);
    EXPECT_EQ(scan.stamp_us.front(), s.stamp) << "the first row's timestamp is the file name";
    const double span_ms = 1e-3 * static_cast<double>(scan.stamp_us.back() - scan.stamp_us.front());
    EXPECT_GT(span_ms, 240.0);  // the sweep: about 252 ms over 400 rows
    EXPECT_LT(span_ms, 260.0);
    for (int a = 1; a < scan.azimuths; ++a) {
      EXPECT_EQ(scan.encoder[a] - scan.encoder[a - 1], 14) << "row " << a;  // 5600 counts / 400 rows
      EXPECT_GE(scan.stamp_us[a], scan.stamp_us[a - 1]);
    }
    EXPECT_EQ(scan.encoder.front(), 13);
    // Encoder 0 is straight ahead and the azimuth grows clockwise: vehicle angle = −2π·enc/5600.
    EXPECT_NEAR(scan.angle[100], -kPi * 2 * scan.encoder[100] / 5600.0, 1e-9);
    EXPECT_NEAR(scan.range_resolution, 0.0438, 1e-12);
  }
}

TEST(OxfordReal, GroundTruthIsAssociatedByRadarTimestampsAndEveryMotionEvaluated) {
  if (!haveData()) GTEST_SKIP() << "no " << kDir << ": skipping the real-data check";
  const ScanningSequence seq(kDir, ScanFormat::Oxford, ScanningSequenceOptions{});
  ASSERT_TRUE(seq.hasGroundTruth());
  const ScanningRunResult r = run("pw-ndt");
  const EvaluationReport rep = evaluate(associate(r.ground_truth, r.estimate), {Metric::Frame});
  EXPECT_EQ(rep.frame->pairs, 10u) << "11 scans, 10 motions";
}

TEST(OxfordReal, OursAgainstPclAndConstantVelocityOnTheTenRealMotions) {
  if (!haveData()) GTEST_SKIP() << "no " << kDir << ": skipping the real-data check";
  const ScanningRunResult ours = run("pw-ndt"), ndt = run("pcl-ndt"), icp = run("pcl-icp");
  const FrameErrors o = frameErrors(ours, false), n = frameErrors(ndt, false), i = frameErrors(icp, false);
  const FrameErrors cv = frameErrors(ours, true);
  for (const auto& [name, e] :
       {std::pair<const char*, FrameErrors>{"ours", o}, {"pcl-ndt", n}, {"pcl-icp", i}, {"constant velocity", cv}})
    std::printf("%-18s frame %.4f m %.4f deg, mean lateral error %+.4f m (%zu motions)\n", name, e.trans, e.rot_deg,
                e.mean_lateral, e.n);
  ASSERT_EQ(o.n, 10u);
  // Absolute: measured 0.070 m and 0.102 deg per frame (2 m steps).
  EXPECT_LT(o.trans, 0.10);
  EXPECT_LT(o.rot_deg, 0.15);
  // No worse than the better of PCL's NDT and ICP by more than 10 % (measured: NDT 0.072 m, 0.102 deg).
  EXPECT_LT(o.trans, 1.1 * std::min(n.trans, i.trans));
  EXPECT_LT(o.rot_deg, 1.1 * std::min(n.rot_deg, i.rot_deg));
  // Clearly better than the constant-velocity guesses it starts from (measured 0.11 m, 0.19 deg):
  // a matcher that returned its guess would do no better than those (it would stand still).
  EXPECT_LT(o.trans, 0.75 * cv.trans);
  EXPECT_LT(o.rot_deg, 0.8 * cv.rot_deg);
}
