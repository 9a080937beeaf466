// The automotive pipeline end to end on real nuScenes scenes (skipped without ../shared/data):
// accuracy and determinism, a one-radar car, and an unreadable sweep.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "radar_ndt/evaluation/report.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/odometry/automotive_odometry.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

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
