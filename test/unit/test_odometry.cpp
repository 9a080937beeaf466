// Odometry: failure handling on a constructed bad matcher, and the automotive pipeline end to end
// on a real nuScenes scene (skipped without ../shared/data).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "radar_ndt/automotive_run.h"
#include "radar_ndt/odometry.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

namespace {

/// A matcher that always "converges" to a 2 m sideways jump: what a match onto a passing truck
/// can look like.
class JumpingMatcher : public RadarRegistration {
 public:
  JumpingMatcher() { reg_name_ = "JumpingMatcher"; }
  int calls = 0;

 protected:
  void computeTransformation(PointCloudSource& output, const Eigen::Matrix4f& guess) override {
    ++calls;
    final_transformation_ = guess;
    final_transformation_(1, 3) += 2.0f;
    pcl::transformPointCloud(*input_, output, final_transformation_);
    converged_ = true;
  }
};

ProcessedCycle constantCycle(std::int64_t t_us, const Eigen::Vector3d& v) {
  ProcessedCycle c;
  c.timestamp_us = t_us;
  for (int i = 0; i < 50; ++i) {
    PointRadar p(static_cast<float>(5 + i), static_cast<float>((i % 7) - 3), 0.f);
    p.cov_xx = p.cov_yy = 0.01f;
    c.cloud->push_back(p);
  }
  c.ego.velocity = v;
  c.ego.covariance = Eigen::Matrix3d::Identity() * 1e-4;
  c.ego.valid = true;
  return c;
}

}  // namespace

TEST(Odometry, ImplausibleMatchesAreRetriedThenFallBackToDoppler) {
  auto matcher = pcl::make_shared<JumpingMatcher>();
  OdometryOptions o;
  Odometry odo(o, matcher);
  const Eigen::Vector3d v(10.0, 0.0, 0.0);
  for (int k = 0; k < 5; ++k) odo.add(constantCycle(k * 75000, v));
  EXPECT_EQ(odo.counters().fallbacks, 4u);
  EXPECT_EQ(matcher->calls, 4 * (o.max_retries + 1));
  const auto& last = odo.steps().back();
  EXPECT_EQ(last.status, StepStatus::Fallback);
  EXPECT_NEAR(last.pose.x(), 4 * 0.75, 1e-9);  // the Doppler integral, not the jumps
  EXPECT_NEAR(last.pose.y(), 0.0, 1e-9);
  // Without the gate the jumps are accepted (what plain submap matching does).
  o.gate = false;
  Odometry ungated(o, pcl::make_shared<JumpingMatcher>());
  for (int k = 0; k < 5; ++k) ungated.add(constantCycle(k * 75000, v));
  EXPECT_EQ(ungated.counters().fallbacks, 0u);
  EXPECT_NEAR(ungated.steps().back().pose.y(), 8.0, 1e-4);
}

TEST(Odometry, DopplerDeadReckoningAndSkippedDuplicateTimestamps) {
  Odometry odo(OdometryOptions{}, nullptr);
  const Eigen::Vector3d v(5.0, 0.0, 0.1);
  odo.add(constantCycle(0, v));
  odo.add(constantCycle(100000, v));
  odo.add(constantCycle(100000, v));  // duplicated timestamp: no second pose
  odo.add(constantCycle(200000, v));
  EXPECT_EQ(odo.counters().skipped, 1u);
  EXPECT_EQ(odo.trajectory().size(), 3u);
  const Pose2 expected = compose(integrateVelocity(v, 0.1), integrateVelocity(v, 0.1));
  EXPECT_TRUE(odo.steps().back().pose.isApprox(expected, 1e-9));
}

TEST(Odometry, InvalidVelocityReusesTheLastOne) {
  Odometry odo(OdometryOptions{}, nullptr);
  odo.add(constantCycle(0, Eigen::Vector3d(5, 0, 0)));
  ProcessedCycle bad = constantCycle(100000, Eigen::Vector3d(50, 0, 0));
  bad.ego.valid = false;
  odo.add(bad);
  EXPECT_EQ(odo.counters().stale_velocity, 1u);
  EXPECT_NEAR(odo.steps().back().pose.x(), 0.5, 1e-9);
}

TEST(AutomotiveOdometry, RealSceneEndToEnd) {
  const std::string root = std::string(RADAR_NDT_SHARED_DATA) + "/nuscenes-mini-radar";
  if (!std::filesystem::exists(root + "/v1.0-mini/sensor.json")) GTEST_SKIP() << "no " << root << ": skipping the real-data check";
  const NuScenesDataset ds(root);
  const AutomotiveRunOptions options;  // defaults: pw-ndt, N = 3, g = 3 m
  const auto r = runAutomotiveOdometry(ds, ds.scene("scene-0103"), options);
  ASSERT_EQ(r.estimate.size(), r.ground_truth.size());
  const EvaluationReport rep = evaluate(associate(r.ground_truth, r.estimate), {Metric::OneMeter});
  // The paper's automotive figures (3.85 %, 0.443 deg/m) with a looser margin for one scene.
  EXPECT_LT(rep.one_meter->trans_err_pct, 5.0);
  EXPECT_LT(rep.one_meter->rot_err_deg_per_m, 0.58);
  EXPECT_LT(static_cast<double>(r.counters.fallbacks), 0.05 * static_cast<double>(r.counters.cycles));
  EXPECT_TRUE(r.problems.empty());
  // Deterministic: a second run gives bit-identical poses.
  const auto again = runAutomotiveOdometry(ds, ds.scene("scene-0103"), options);
  for (std::size_t i = 0; i < r.estimate.size(); ++i) EXPECT_EQ(r.estimate.poses[i].matrix(), again.estimate.poses[i].matrix());
}

TEST(AutomotiveOdometry, OneRadarCarRunsOnTheNonholonomicEgoVelocity) {
  // Only the front radar: its Doppler sees 2 of the 3 velocity components, so every cycle's
  // ego-velocity takes vy = 0 (before, every cycle was invalid and the run stood still: ~90 %).
  const std::string root = std::string(RADAR_NDT_SHARED_DATA) + "/nuscenes-mini-radar";
  if (!std::filesystem::exists(root + "/v1.0-mini/sensor.json")) GTEST_SKIP() << "no " << root << ": skipping the real-data check";
  const NuScenesDataset ds(root);
  AutomotiveRunOptions options;
  options.sequence.channels = {"RADAR_FRONT"};
  const auto r = runAutomotiveOdometry(ds, ds.scene("scene-0103"), options);
  EXPECT_EQ(r.invalid_velocity_cycles, 0u);
  EXPECT_EQ(r.nonholonomic_velocity_cycles, r.counters.cycles);
  const EvaluationReport rep = evaluate(associate(r.ground_truth, r.estimate), {Metric::OneMeter});
  EXPECT_LT(rep.one_meter->trans_err_pct, 5.0);  // measured 2.78 % (all five radars: 1.5-2 %)
  EXPECT_LT(rep.one_meter->rot_err_deg_per_m, 0.58);
  EXPECT_LT(static_cast<double>(r.counters.fallbacks), 0.05 * static_cast<double>(r.counters.cycles));
  EXPECT_THROW(
      [&] {
        AutomotiveRunOptions bad;
        bad.sequence.channels = {"RADAR_NOSE"};
        runAutomotiveOdometry(ds, ds.scene("scene-0103"), bad);
      }(),
      std::invalid_argument);
}

TEST(AutomotiveOdometry, UnreadableSweepCostsOnlyThatSweep) {
  const std::string root = std::string(RADAR_NDT_SHARED_DATA) + "/nuscenes-mini-radar";
  if (!std::filesystem::exists(root + "/v1.0-mini/sensor.json")) GTEST_SKIP() << "no " << root << ": skipping the real-data check";
  // A copy of the tables with the real sweep folders linked, and one sweep replaced by garbage.
  namespace fs = std::filesystem;
  const std::string copy = ::testing::TempDir() + "radar_ndt_odo_root";
  fs::remove_all(copy);
  fs::create_directories(copy);
  fs::create_directory_symlink(root + "/v1.0-mini", copy + "/v1.0-mini");
  fs::create_directories(copy + "/sweeps");
  fs::create_directory_symlink(root + "/samples", copy + "/samples");
  for (const auto& d : fs::directory_iterator(root + "/sweeps")) {
    if (d.path().filename() != "RADAR_FRONT_LEFT") {
      fs::create_directory_symlink(d.path(), copy + "/sweeps/" + d.path().filename().string());
      continue;
    }
    fs::create_directories(copy + "/sweeps/RADAR_FRONT_LEFT");
    std::vector<fs::path> files;
    for (const auto& f : fs::directory_iterator(d.path())) files.push_back(f.path());
    std::sort(files.begin(), files.end());  // names end in the timestamp: time order within a scene
    std::size_t n0061 = 0;
    for (const auto& f : files) {
      const std::string target = copy + "/sweeps/RADAR_FRONT_LEFT/" + f.filename().string();
      if (f.filename().string().find("scene-0061") != std::string::npos && ++n0061 == 10)
        std::ofstream(target) << "VERSION 0.7\nFIELDS x y\n";  // the 10th sweep: a truncated header
      else
        fs::create_symlink(f, target);
    }
  }
  const NuScenesDataset ds(copy);
  AutomotiveRunOptions options;
  options.max_cycles = 80;
  const auto r = runAutomotiveOdometry(ds, ds.scene("scene-0061"), options);
  ASSERT_EQ(r.problems.size(), 1u);  // the broken sweep, named, with the reason
  EXPECT_NE(r.problems[0].find("RADAR_FRONT_LEFT"), std::string::npos) << r.problems[0];
  EXPECT_NE(r.problems[0].find("no DATA line"), std::string::npos) << r.problems[0];
  EXPECT_EQ(r.estimate.size(), 80u);
}
