// The scanning pipeline: Odometry::addScan and runScanningOdometry end to end on simulated
// Oxford-layout sequences, the failure handling on a constructed bad match (a bus filling the
// view), motion compensation on a fast turn, and plausibility on the real RADIATE scans
// (skipped without ../shared/data).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "radar_ndt/evaluation_report.h"
#include "radar_ndt/metrics.h"
#include "radar_ndt/odometry.h"
#include "radar_ndt/radar_sim.h"
#include "radar_ndt/scanning_run.h"
#include "radar_ndt/top_view_map.h"
#include "test_support.h"

using namespace radar_ndt;

namespace {

EvaluationReport frameErrors(const ScanningRunResult& r) {
  return evaluate(associate(r.ground_truth, r.estimate), {Metric::Frame});
}

/// A constant-radius turn at `speed` after a short straight: the fast-turn case.
sim::SimTrajectory turningDrive(double speed, double radius, double duration) {
  std::vector<double> stamps;
  std::vector<Pose2> poses;
  const double w = speed / radius;
  for (double t = 0; t <= duration + 1e-9; t += 0.25) {  // one pose per 4 Hz scan
    stamps.push_back(t);
    if (t < 2.0) {
      poses.emplace_back(speed * t, 0.0, 0.0);
    } else {
      const double a = w * (t - 2.0);
      poses.emplace_back(2.0 * speed + radius * std::sin(a), radius * (1.0 - std::cos(a)), a);
    }
  }
  return sim::SimTrajectory(stamps, poses);
}

}  // namespace

TEST(SE2, VelocityOfInvertsIntegrateVelocity) {
  for (const Eigen::Vector3d& v : {Eigen::Vector3d(10, 0.3, 0.5), Eigen::Vector3d(-2, 1, -1.2), Eigen::Vector3d(5, 0, 0)}) {
    const Eigen::Vector3d back = velocityOf(integrateVelocity(v, 0.25), 0.25);
    EXPECT_LT((back - v).norm(), 1e-9) << v.transpose();
  }
}

TEST(CompensateMotion, MovesPointsToTheReferenceTime) {
  // The vehicle drives at 10 m/s turning at 0.5 rad/s; a wall point measured at τ = 0.2 s, seen
  // from the pose then, is moved into the frame at τ = 0.
  const Eigen::Vector3d v(10, 0, 0.5);
  const Pose2 at_tau = integrateVelocity(v, 0.2);
  const Eigen::Vector2d world(20, 5);  // in the frame at τ = 0
  const Eigen::Vector2d seen = toIsometry2<double>(at_tau).inverse() * world;
  pcl::PointCloud<PointRadar> cloud, out;
  PointRadar p(static_cast<float>(seen.x()), static_cast<float>(seen.y()), 0.f);
  p.time_offset = 0.2f;
  p.cov_xx = 0.04f;
  p.cov_yy = 0.01f;
  cloud.push_back(p);
  compensateMotion(cloud, v, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].x, world.x(), 2e-3);
  EXPECT_NEAR(out[0].y, world.y(), 2e-3);
  EXPECT_EQ(out[0].time_offset, 0.f);
  EXPECT_NEAR(out[0].cov_xx + out[0].cov_yy, 0.05f, 1e-6);  // a rotation keeps the trace
}

TEST(ScanningOdometry, EndToEndOnASimulatedDrive) {
  const std::string dir = test::freshTempDir("scanning_e2e");
  sim::SequenceOptions seq;
  seq.start = 40;  // moving, with a turn ahead
  seq.frames = 60;
  sim::writeScanningSequence(dir, sim::builtinDrive(60.0), sim::WorldOptions(), sim::ScanningOptions(), seq);
  const ScanningSequence sequence(dir, ScanFormat::Oxford);
  ASSERT_TRUE(sequence.hasGroundTruth());
  const ScanningRunResult r = runScanningOdometry(sequence, ScanningRunOptions());
  ASSERT_EQ(r.estimate.size(), 60u);
  EXPECT_TRUE(r.problems.empty());
  EXPECT_LE(r.counters.fallbacks, 2u);
  const EvaluationReport rep = frameErrors(r);
  EXPECT_LT(rep.frame->trans_err_m, 0.08);
  EXPECT_LT(rep.frame->rot_err_deg, 0.2);
  // Accumulated: the end pose within 2 % of the distance driven.
  const Pose2 end_est = toPose2(r.estimate.poses.back()), end_gt = toPose2(r.ground_truth.poses.back());
  double driven = 0;
  for (std::size_t k = 1; k < r.ground_truth.size(); ++k)
    driven += (r.ground_truth.poses[k].translation() - r.ground_truth.poses[k - 1].translation()).norm();
  EXPECT_GT(driven, 50.0);
  EXPECT_LT((end_est.head<2>() - end_gt.head<2>()).norm(), 0.02 * driven);
}

TEST(ScanningOdometry, UnreadableScanIsReportedAndSkipped) {
  const std::string dir = test::freshTempDir("scanning_bad_frame");
  sim::SequenceOptions seq;
  seq.start = 40;
  seq.frames = 12;
  sim::writeScanningSequence(dir, sim::builtinDrive(30.0), sim::WorldOptions(), sim::ScanningOptions(), seq);
  const ScanningSequence sequence(dir, ScanFormat::Oxford);
  {
    std::ofstream truncate(sequence.path(6), std::ios::binary | std::ios::trunc);
    truncate << "\x89PNG";
  }
  const ScanningRunResult r = runScanningOdometry(sequence, ScanningRunOptions());
  ASSERT_EQ(r.problems.size(), 1u);
  EXPECT_NE(r.problems[0].find(sequence.path(6)), std::string::npos) << r.problems[0];
  EXPECT_EQ(r.estimate.size(), 11u);
  const EvaluationReport rep = frameErrors(r);
  EXPECT_LT(rep.frame->trans_err_m, 0.15) << "the scan after the gap is matched over twice the interval";
}

TEST(ScanningOdometry, BusFillingTheViewTriggersTheFailureHandling) {
  // A static scene of weak returns and, from scan 4 on, a bus alongside moving with the car:
  // strong, dense and fixed in the vehicle frame, so it pulls the match to zero motion. The
  // motion prior must reject that, retry (bigger grids, then s halved) and fall back to constant
  // velocity if nothing passes, leaving the trajectory close to the truth.
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.f, 0.03f);
  std::vector<Eigen::Vector2d> world;
  for (double x = -60; x <= 200; x += 0.5) {  // two facades with gaps and some poles
    if (std::fmod(x + 60, 17.0) < 13.0) {
      world.emplace_back(x, 9.0);
      world.emplace_back(x, -11.0);
    }
    if (std::fmod(x + 60, 23.0) < 0.5) world.emplace_back(x, 6.5 + std::fmod(x, 3.0));
  }
  const double step = 2.5;  // 10 m/s at 4 Hz
  OdometryOptions options;
  options.scanning.keyframe_distance = 0;  // scan to scan: every step sees the bus in its target
  Odometry odometry(options, makeMatcher(Method::PwNdt, options.scanning.grid));
  for (int k = 0; k < 9; ++k) {
    pcl::PointCloud<PointRadar>::Ptr cloud(new pcl::PointCloud<PointRadar>);
    const double x0 = step * k;
    for (const auto& w : world) {
      const double x = w.x() - x0, y = w.y();
      if (std::hypot(x, y) > 60) continue;
      PointRadar p(static_cast<float>(x) + noise(rng), static_cast<float>(y) + noise(rng), 0.f, 0.45f);
      p.cov_xx = p.cov_yy = 0.01f;
      cloud->push_back(p);
    }
    if (k >= 4)  // the bus: 12 m x 2.5 m beside the car, densely filled and saturated
      for (double bx = -4; bx <= 8; bx += 0.125)
        for (double by = 2.5; by <= 5.0; by += 0.125) {
          PointRadar p(static_cast<float>(bx), static_cast<float>(by), 0.f, 1.0f);
          p.cov_xx = p.cov_yy = 0.01f;
          cloud->push_back(p);
        }
    odometry.addScan(ScanFrame{1000000 + 250000 * k, cloud});
  }
  const auto& c = odometry.counters();
  EXPECT_GE(c.retried + c.fallbacks, 1u) << "the bus steps must not pass at the nominal grid";
  for (std::size_t k = 5; k < odometry.steps().size(); ++k) {
    const OdometryStep& s = odometry.steps()[k];
    EXPECT_GT(s.motion.x(), 1.5) << "step " << k << " (" << toString(s.status) << ") accepted the bus's zero motion";
  }
  EXPECT_NEAR(odometry.steps().back().pose.x(), step * 8, 1.0);
  EXPECT_NEAR(odometry.steps().back().pose.y(), 0.0, 0.5);
}

TEST(ScanningOdometry, MotionCompensationHelpsOnAFastTurn) {
  const std::string dir = test::freshTempDir("scanning_turn");
  sim::SequenceOptions seq;
  seq.frames = 40;
  sim::writeScanningSequence(dir, turningDrive(10.0, 20.0, 12.0), sim::WorldOptions(), sim::ScanningOptions(), seq);
  const ScanningSequence sequence(dir, ScanFormat::Oxford);
  ScanningRunOptions on, off;
  off.odometry.scanning.motion_compensation = false;
  const EvaluationReport with = frameErrors(runScanningOdometry(sequence, on));
  const EvaluationReport without = frameErrors(runScanningOdometry(sequence, off));
  // 0.5 rad/s: over a 0.25 s sweep the heading turns 7°, which a scan-to-scan match mistakes for
  // part of the rotation between scans.
  EXPECT_LT(with.frame->rot_err_deg, 0.9 * without.frame->rot_err_deg)
      << "with " << with.frame->rot_err_deg << " deg, without " << without.frame->rot_err_deg << " deg";
  EXPECT_LT(with.frame->trans_err_m, 1.1 * without.frame->trans_err_m);
}

TEST(ScanningOdometry, RadiateScansArePlausible) {
  const std::string dir = std::string(RADAR_NDT_SHARED_DATA) + "/radiate-tiny-foggy";
  if (!std::filesystem::exists(dir + "/Navtech_Polar.txt")) GTEST_SKIP() << "no " << dir << ": skipping the real-scan check";
  const ScanningSequence sequence(dir, ScanFormat::Radiate);
  std::vector<pcl::PointCloud<PointRadar>> clouds;
  const ScanningRunResult r = runScanningOdometry(sequence, ScanningRunOptions(), nullptr,
                                                  [&](std::size_t, const OdometryStep&, const pcl::PointCloud<PointRadar>& c) { clouds.push_back(c); });
  ASSERT_EQ(r.steps.size(), sequence.size());
  EXPECT_TRUE(r.problems.empty());
  EXPECT_LE(r.counters.fallbacks, 1u) << "no fallback storm";
  for (std::size_t k = 1; k < r.steps.size(); ++k) {
    const double dt = 1e-6 * static_cast<double>(r.steps[k].timestamp_us - r.steps[k - 1].timestamp_us);
    const Eigen::Vector3d v = velocityOf(r.steps[k].motion, dt);
    EXPECT_LT(v.head<2>().norm(), 40.0) << "scan " << k;   // m/s: a car in town
    EXPECT_LT(std::abs(v.y()), 1.5) << "scan " << k;        // no sideways slide
    EXPECT_LT(std::abs(v.z()), 1.0) << "scan " << k;        // rad/s
    if (k >= 2) {
      const double dt0 = 1e-6 * static_cast<double>(r.steps[k - 1].timestamp_us - r.steps[k - 2].timestamp_us);
      const Eigen::Vector3d v0 = velocityOf(r.steps[k - 1].motion, dt0);
      EXPECT_LT((v - v0).head<2>().norm() / dt, 8.0) << "scan " << k;  // m/s²
    }
  }
  // Sharp, not doubled: the scans at the estimated poses cover fewer map pixels than at poses
  // with the motion scaled by ±10 % (which would double every structure across the path).
  auto occupancy = [&](double scale) {
    TopViewMap map(0.2);
    Pose2 pose = Pose2::Zero();
    for (std::size_t k = 0; k < clouds.size(); ++k) {
      if (k > 0) pose = compose(pose, scale * r.steps[k].motion);
      map.add(clouds[k], pose);
    }
    return map.occupiedPixels();
  };
  const std::size_t estimated = occupancy(1.0);
  EXPECT_LT(estimated, occupancy(0.9));
  EXPECT_LT(estimated, occupancy(1.1));
}
