#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "radar_ndt/evaluation/metrics.h"
#include "radar_ndt/evaluation/report.h"
#include "radar_ndt/io/trajectory_io.h"

using namespace radar_ndt;

namespace {
/// A planar drive: straight, then a constant-radius turn, one pose every `ds` metres.
Trajectory drive(std::size_t n, double ds, double turn_per_m = 0.002) {
  Trajectory t;
  Pose2 p = Pose2::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    t.poses.push_back(toIsometry3(p));
    t.stamps.push_back(100.0 + 0.25 * static_cast<double>(i));
    const double yaw_rate = i > n / 3 ? turn_per_m : 0.0;
    p = compose(p, Pose2(ds, 0, yaw_rate * ds));
  }
  return t;
}

/// The same motions with every step scaled by (1 + scale_err): a pure translational drift.
Trajectory scaled(const Trajectory& gt, double scale_err) {
  Trajectory e;
  e.stamps = gt.stamps;
  Eigen::Isometry3d acc = gt.poses[0];
  e.poses.push_back(acc);
  for (std::size_t i = 1; i < gt.size(); ++i) {
    Eigen::Isometry3d d = gt.poses[i - 1].inverse() * gt.poses[i];
    d.translation() *= 1.0 + scale_err;
    acc = acc * d;
    e.poses.push_back(acc);
  }
  return e;
}

PosePairs byIndex(const Trajectory& a, const Trajectory& b) {
  Trajectory x = a, y = b;
  x.stamps.clear();
  y.stamps.clear();
  return associate(x, y);
}
}  // namespace

TEST(Metrics, PerfectEstimateHasZeroError) {
  const auto gt = drive(4000, 0.5);
  const auto p = byIndex(gt, gt);
  const auto k = kittiError(p);
  EXPECT_GT(k.segments, 0u);
  EXPECT_NEAR(k.trans_err_pct, 0, 1e-9);
  EXPECT_NEAR(k.rot_err_deg_per_m, 0, 1e-6);
  EXPECT_NEAR(frameError(p).trans_err_m, 0, 1e-12);
  EXPECT_NEAR(absoluteTrajectoryError(p).rmse_m, 0, 1e-9);
}

TEST(Metrics, KittiSegmentsFollowTheDevkit) {
  const auto gt = drive(2000, 1.0);  // 1999 m of path, a pose every metre
  const auto k = kittiError(byIndex(gt, gt));
  ASSERT_EQ(k.per_length.size(), 8u);
  // first frames 0, 10, ...; L = 100: the last frame is first + 101 (path > 100 m), so first <= 1898.
  EXPECT_EQ(k.per_length[0].segments, 190u);
  EXPECT_EQ(k.per_length[7].segments, 120u);  // first + 801 <= 1999
}

TEST(Metrics, ScaleDriftGivesThatPercentage) {
  const auto gt = drive(4000, 0.5, 0.0);  // straight line: a 1 % scale error is exactly 1 % per segment
  const auto p = byIndex(gt, scaled(gt, 0.01));
  EXPECT_NEAR(kittiError(p).trans_err_pct, 1.0, 0.03);  // segments end just past L
  EXPECT_NEAR(kittiError(p).rot_err_deg_per_m, 0.0, 1e-9);
  EXPECT_NEAR(frameError(p).trans_err_m, 0.005, 1e-9);
  EXPECT_NEAR(oneMeterError(p).trans_err_pct, 1.0, 1e-6);  // divided by the actual length
}

TEST(Metrics, OneMeterDividesByActualPathLength) {
  // 13 Hz at 18 m/s: 1.385 m per cycle, so each "1 m" segment is one step of 1.385 m.
  const auto gt = drive(200, 1.385, 0.0);
  auto est = gt;
  for (std::size_t i = 0; i < est.size(); ++i) est.poses[i].translation().y() += (i % 2) ? 0.01385 : 0.0;
  const auto r = oneMeterError(byIndex(gt, est));
  EXPECT_EQ(r.segments, 199u);
  EXPECT_NEAR(r.trans_err_pct, 1.0, 1e-6);  // 1.385 cm over 1.385 m, not over 1 m
}

TEST(Metrics, AteRemovesARigidOffsetAndRotation) {
  const auto gt = drive(1000, 0.5);
  auto est = gt;
  const Eigen::Isometry3d off = toIsometry3(Pose2(50, -20, 0.8));
  for (auto& T : est.poses) T = off * T;
  const auto a = absoluteTrajectoryError(byIndex(gt, est));
  EXPECT_NEAR(a.rmse_m, 0, 1e-8);
  EXPECT_NEAR(std::abs(a.alignment.z()), 0.8, 1e-9);
}

TEST(Metrics, FrameStepSubsamples) {
  const auto gt = drive(100, 0.5, 0.0);
  const auto p = byIndex(gt, scaled(gt, 0.1));
  const auto f3 = frameError(p, 3);
  EXPECT_EQ(f3.pairs, 33u);
  EXPECT_NEAR(f3.trans_err_m, 0.15, 1e-9);
}

TEST(Metrics, TimestampAssociationInterpolatesGroundTruth) {
  const auto gt = drive(400, 0.5);
  Trajectory est;
  for (std::size_t i = 0; i + 1 < gt.size(); i += 3) {  // estimates half-way between gt poses
    const double t = 0.5 * (gt.stamps[i] + gt.stamps[i + 1]);
    est.stamps.push_back(t);
    Eigen::Isometry3d T = gt.poses[i];
    T.translation() = 0.5 * (gt.poses[i].translation() + gt.poses[i + 1].translation());
    est.poses.push_back(T);
  }
  est.stamps.push_back(gt.stamps.back() + 10);  // outside: dropped
  est.poses.push_back(gt.poses.back());
  const auto p = associate(gt, est);
  EXPECT_EQ(p.size(), est.size() - 1);
  for (std::size_t i = 0; i < p.size(); ++i)
    EXPECT_NEAR((p.gt[i].translation() - p.est[i].translation()).norm(), 0, 1e-9);
}

TEST(Metrics, AssociationFailuresAreClear) {
  const auto gt = drive(100, 0.5);
  auto shorter = gt;
  shorter.poses.pop_back();
  shorter.stamps.clear();
  EXPECT_THROW(associate(gt, shorter), std::invalid_argument);
  auto later = gt;
  for (auto& s : later.stamps) s += 1000;
  EXPECT_THROW(associate(gt, later), std::invalid_argument);
}

TEST(Metrics, AnErrorWithNothingToAverageIsUndefinedNotZero) {
  // 40 m of driving: no KITTI segment (the shortest is 100 m). A zero there would read as a perfect
  // estimate; it is NaN, "n/a" in the table and null in JSON.
  const auto short_gt = drive(80, 0.5);
  const auto r = evaluate(byIndex(short_gt, scaled(short_gt, 0.01)), parseMetrics("kitti,frame"));
  ASSERT_TRUE(r.kitti);
  EXPECT_EQ(r.kitti->segments, 0u);
  EXPECT_TRUE(std::isnan(r.kitti->trans_err_pct));
  EXPECT_TRUE(std::isnan(r.kitti->rot_err_deg_per_m));
  for (const auto& pl : r.kitti->per_length) EXPECT_TRUE(std::isnan(pl.trans_err_pct)) << pl.length;
  EXPECT_GT(r.frame->pairs, 0u);
  const std::string table = formatTable(r);
  EXPECT_NE(table.find("n/a"), std::string::npos) << table;
  EXPECT_NE(table.find("shorter than 100 m"), std::string::npos) << table;
  EXPECT_EQ(table.find("0.00000 %"), std::string::npos) << table;
  EXPECT_NE(toJson(r).find("\"trans_err_pct\": null"), std::string::npos) << toJson(r);

  // The mean over runs takes each error where it is defined and sums the counts.
  const auto long_gt = drive(3000, 0.5);
  const auto longer = evaluate(byIndex(long_gt, scaled(long_gt, 0.01)), parseMetrics("kitti,frame"));
  const EvaluationReport mean = meanReport({r, longer});
  EXPECT_DOUBLE_EQ(mean.kitti->trans_err_pct, longer.kitti->trans_err_pct);
  EXPECT_EQ(mean.kitti->segments, longer.kitti->segments);
  EXPECT_DOUBLE_EQ(mean.frame->trans_err_m, 0.5 * (r.frame->trans_err_m + longer.frame->trans_err_m));
  EXPECT_EQ(mean.frame->pairs, r.frame->pairs + longer.frame->pairs);
  EXPECT_TRUE(std::isnan(meanReport({r, r}).kitti->trans_err_pct));
}

// The published evaluation (CFEAR-3 on Oxford, its authors' own code): ../shared/data/kitti-metric-fixture.
TEST(Metrics, MatchesThePublishedKittiFixture) {
  const std::string dir = std::string(RADAR_NDT_SHARED_DATA) + "/kitti-metric-fixture";
  if (!std::filesystem::exists(dir + "/gt.txt"))
    GTEST_SKIP() << "no " << dir << " (../shared/data is absent): skipping the published-fixture check";
  const auto p = associate(readKitti(dir + "/gt.txt"), readKitti(dir + "/est.txt"));
  const auto k = kittiError(p);
  EXPECT_NEAR(k.trans_err_pct, 1.23125, 0.001);
  EXPECT_NEAR(k.rot_err_deg_per_m * 100.0, 0.35856, 0.001);  // result.txt gives deg/100m
  const auto f = frameError(p);
  EXPECT_NEAR(f.trans_err_m, 0.05212, 0.0001);
  // Published 0.05227, from the 6-decimal blocks as written; here projected onto rotations (near the
  // identity acos of the rounded trace is noise of about 1e-3 rad a frame).
  EXPECT_NEAR(f.rot_err_deg, 0.04777, 0.0002);
  EXPECT_NEAR(absoluteTrajectoryError(p).rmse_m, 7.68966, 0.001);
}

// The Boreas SDK's odometry evaluation (pyboreas eval/odometry.py, radar benchmark) on CFEAR's
// published files: ../shared/data/boreas-eval-fixture (its README gives the SDK's figures).
TEST(Metrics, MatchesTheBoreasSdkOnPublishedFiles) {
  const std::string dir = std::string(RADAR_NDT_SHARED_DATA) + "/boreas-eval-fixture";
  if (!std::filesystem::exists(dir + "/leaderboard"))
    GTEST_SKIP() << "no " << dir << " (../shared/data is absent): skipping the Boreas SDK check";
  struct Sdk {
    const char* sequence;
    double step4_pct, step4_deg_per_100m, step10_pct, step10_deg_per_100m;
  };
  for (const Sdk& sdk : {Sdk{"boreas-2020-11-26-13-58", 0.79356, 0.23836, 0.79253, 0.23690},
                         Sdk{"boreas-2021-08-05-13-34", 0.89190, 0.23049, 0.88281, 0.22917}}) {
    const std::string name = std::string(sdk.sequence) + ".txt";
    const Trajectory gt = readTrajectory(dir + "/leaderboard/gt/" + name);
    const Trajectory est = readTrajectory(dir + "/leaderboard/est/" + name);
    EXPECT_GT(est.projected_rotations, 0u) << "5 decimals: the blocks need the SDK's re-orthogonalisation";
    const PosePairs p = associate(gt, est);
    ASSERT_EQ(p.size(), gt.size());
    const std::vector<double> lengths{100, 200, 300, 400, 500, 600, 700, 800};
    const SegmentError k4 = kittiError(p, lengths, 4);
    const SegmentError k10 = kittiError(p, lengths, 10);
    // The SDK prints 5 significant digits: agreement to 1e-4 relative, beyond its rounding.
    auto expectClose = [&](double ours, double theirs, const char* what) {
      EXPECT_LT(std::abs(ours - theirs), 1e-4 * theirs + 0.5e-5) << sdk.sequence << " " << what << ": " << ours;
    };
    expectClose(k4.trans_err_pct, sdk.step4_pct, "step 4 translation");
    expectClose(k4.rot_err_deg_per_m * 100.0, sdk.step4_deg_per_100m, "step 4 rotation");
    expectClose(k10.trans_err_pct, sdk.step10_pct, "step 10 translation");
    expectClose(k10.rot_err_deg_per_m * 100.0, sdk.step10_deg_per_100m, "step 10 rotation");
    // The same trajectories as CFEAR ships them for its own evaluator, 3 decimals: read, projected.
    const Trajectory rounded = readTrajectory(dir + "/kitti-3-decimals/est/" + name);
    EXPECT_EQ(rounded.size(), est.size());
    EXPECT_GT(rounded.projected_rotations, rounded.size() / 2);
    EXPECT_GT(rounded.max_rotation_deviation, 1e-4);
  }
}
