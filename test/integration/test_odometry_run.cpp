// The one run entry (radar_ndt/pipeline/odometry_run.h) and the settings it takes
// (radar_ndt/pipeline/run_settings.h): a source opened through it runs as the pipelines run it
// directly, bit for bit; the live stream of cycles gives the offline run's steps; settings the
// pipeline does not use are refused with why. Real data from ../shared/data (skipped when absent).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "radar_ndt/io/nuscenes_sequence.h"
#include "radar_ndt/pipeline/odometry_run.h"
#ifdef RADAR_NDT_WITH_ROS
#include "radar_ndt/ros/bag_reader.h"
#include "radar_ndt/ros/nuscenes_bag.h"
#include "radar_ndt/ros/rosbag_sequence.h"
#endif

using namespace radar_ndt;
namespace fs = std::filesystem;

namespace {

const std::string kData = RADAR_NDT_SHARED_DATA;
const std::string kNuScenes = kData + "/nuscenes-mini-radar";
const std::string kOxford = kData + "/oxford-radar-real";

#define REQUIRE_PATH(p) \
  if (!fs::exists(p)) GTEST_SKIP() << "no " << (p) << " (../shared/data is absent)"

void expectSameTrajectory(const Trajectory& a, const Trajectory& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a.stamps[k], b.stamps[k]) << what << " " << k;
    ASSERT_TRUE(a.poses[k].matrix() == b.poses[k].matrix()) << what << " pose " << k;
  }
}

/// The reason a build of settings is refused, or "accepted".
template <typename F>
std::string refusal(F&& build, SettingError::Why* why = nullptr) {
  try {
    build();
  } catch (const SettingError& e) {
    if (why) *why = e.why();
    return e.what();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST(OdometryRun, ASequenceRunsAsTheScanningRunDoesWithTheSettingsApplied) {
  REQUIRE_PATH(kOxford);
  const Settings given{{"matcher.grid", FieldValue(4.0), "--grid"}, {"threads", FieldValue(1), ""}};
  const OdometryRun run(RunSource{"oxford", kOxford, "", "", ""}, given);
  ASSERT_EQ(run.pipeline(), PipelineKind::Scanning);
  EXPECT_EQ(run.scanningOptions().matcher.grid, 4.0);
  EXPECT_TRUE(run.hasGroundTruth());
  ScanningRunOptions direct_options;
  direct_options.matcher.grid = 4.0;
  direct_options.threads = 1;
  const ScanningSequence sequence(kOxford, ScanFormat::Oxford);
  const ScanningRunResult direct = runScanningOdometry(sequence, direct_options);
  const ScanningRunResult entered = run.runScanning();
  expectSameTrajectory(entered.estimate, direct.estimate, "oxford");
  EXPECT_EQ(entered.prior, direct.prior);
  EXPECT_THROW(run.automotiveOptions(), std::logic_error);
}

TEST(OdometryRun, AScenesAndEveryScenesRunsAreTheDirectRuns) {
  REQUIRE_PATH(kNuScenes);
  const Settings given{{"max_cycles", FieldValue(40), ""}};
  const std::vector<OdometryRun> runs = OdometryRun::openAll(RunSource{"nuscenes", kNuScenes, "all", "", ""}, given);
  const NuScenesDataset dataset(kNuScenes);
  ASSERT_EQ(runs.size(), dataset.scenes().size());
  AutomotiveRunOptions o;
  o.max_cycles = 40;
  std::vector<AutomotiveRunResult> side(runs.size());
  runSideBySide(runs, [&](std::size_t i, const AutomotiveRunResult& r) { side[i] = r; });
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const AutomotiveRunResult direct = runAutomotiveOdometry(dataset, dataset.scenes()[i], o);
    expectSameTrajectory(side[i].estimate, direct.estimate, runs[i].name());
    if (i == 1) expectSameTrajectory(runs[i].runAutomotive().estimate, direct.estimate, runs[i].name());
  }
  const OdometryRun one(RunSource{"nuscenes", kNuScenes, "scene-0103", "", ""}, given);
  EXPECT_EQ(one.name(), "scene-0103");
  EXPECT_THROW(OdometryRun(RunSource{"nuscenes", kNuScenes, "all", "", ""}, given), std::invalid_argument);
  EXPECT_THROW(OdometryRun(RunSource{"navtech", kOxford, "", "", ""}, {}), std::invalid_argument);
}

TEST(OdometryRun, TheStreamOfCyclesGivesTheOfflineRunsSteps) {
  REQUIRE_PATH(kNuScenes);
  // What the ROS node runs a cycle at a time: the offline run's per-cycle step.
  const NuScenesDataset dataset(kNuScenes);
  const NuScenesScene& scene = dataset.scene("scene-0655");
  AutomotiveRunOptions o;
  o.threads = 1;
  const AutomotiveRunResult offline = runAutomotiveOdometry(dataset, scene, o);
  const NuScenesRadarSequence cycles(dataset, scene);
  AutomotiveStream stream(o, nullptr, scene.name);
  for (std::size_t k = 0; k < cycles.size(); ++k) {
    const AutomotiveStream::Added a = stream.add(cycles.load(k));
    ASSERT_TRUE(a.step.pose.isApprox(offline.steps[k].pose, 0.0)) << "cycle " << k;
  }
  const AutomotiveRunResult live = stream.result();
  expectSameTrajectory(live.estimate, offline.estimate, "stream");
  EXPECT_EQ(live.counters.matched, offline.counters.matched);
  EXPECT_EQ(live.prior, offline.prior);
  EXPECT_THROW(AutomotiveStream(withMethod(o, "wheel-gyro")), std::invalid_argument) << "the car's sensors, none given";
}

TEST(RunSettings, ASettingThePipelineDoesNotUseIsRefusedWithWhy) {
  SettingError::Why why{};
  std::string text = refusal(
      [] {
        automotiveRunOptions({{"front_end.threshold", FieldValue(0.3), "--threshold"}});
      },
      &why);
  EXPECT_EQ(why, SettingError::Why::OtherPipeline) << text;
  EXPECT_NE(text.find("--threshold"), std::string::npos) << text;
  text = refusal([] { automotiveRunOptions({{"odometry.fuse_dopler", FieldValue(true), ""}}); }, &why);
  EXPECT_EQ(why, SettingError::Why::NoSuchSetting) << text;
  EXPECT_NE(text.find("fuse_doppler"), std::string::npos) << "the fields beside it: " << text;
  text = refusal(
      [] {
        scanningRunOptions({{"sequence.boreas.range_resolution", FieldValue(0.05), ""}}, "oxford");
      },
      &why);
  EXPECT_EQ(why, SettingError::Why::NotThisLayout) << text;
  text = refusal([] { automotiveRunOptions({{"matcher.grid", FieldValue("four"), ""}}); }, &why);
  EXPECT_EQ(why, SettingError::Why::Type) << text;
  text = refusal([] { automotiveRunOptions({{"matcher.grid", FieldValue(-1.0), ""}}); }, &why);
  EXPECT_EQ(why, SettingError::Why::Value) << text;
  // The method sets what it needs; a given setting that contradicts it is refused by validate().
  EXPECT_TRUE(automotiveRunOptions({{"matcher.method", FieldValue("rapp-ndt"), ""}}).odometry.doppler_weights);
  text = refusal([] {
    automotiveRunOptions(
        {{"matcher.method", FieldValue("rapp-ndt"), ""}, {"front_end.remove_moving", FieldValue(true), ""}});
  });
  EXPECT_NE(text.find("remove_moving"), std::string::npos) << text;
  // The paper's mode is not fused, unless the fusion is given.
  EXPECT_FALSE(automotiveRunOptions({{"odometry.mode", FieldValue("submap-to-submap"), ""}}).odometry.fuse_doppler);
  EXPECT_TRUE(automotiveRunOptions({{"odometry.mode", FieldValue("submap-to-submap"), ""},
                                    {"odometry.fuse_doppler", FieldValue(true), ""}})
                  .odometry.fuse_doppler);
}

#ifdef RADAR_NDT_WITH_ROS
TEST(OdometryRun, ARecordingRunsThroughItsDescriptionWithTheRadarsTheSettingsChoose) {
  REQUIRE_PATH(kNuScenes);
  ros1::registerBagReader();
  const NuScenesDataset dataset(kNuScenes);
  const NuScenesScene& scene = dataset.scene("scene-0103");
  const std::string bag = (fs::temp_directory_path() / "odometry_run_scene-0103.bag").string();
  ros1::writeNuScenesBag(dataset, scene, bag, ros1::BagCompression::None);
  const Settings given{{"sequence.channels", FieldValue(FieldValue::List{"RADAR_FRONT", "RADAR_BACK_LEFT"}), ""},
                       {"sequence.reference_channel", FieldValue("RADAR_BACK_LEFT"), ""},
                       {"odometry.car.gyro", FieldValue(true), "--imu"}};
  const OdometryRun run(RunSource{"rosbag", bag, "", "", "preset:nuscenes_ars408"}, given);
  ASSERT_EQ(run.pipeline(), PipelineKind::Automotive);
  const AutomotiveRunResult entered = run.runAutomotive();
  EXPECT_EQ(entered.reference_channel, "RADAR_BACK_LEFT");
  // The same through the bag reader and the description the settings make.
  const SensorDescription d =
      describedSensors(readSensorDescription("preset:nuscenes_ars408"), run.automotiveOptions(), given);
  ASSERT_EQ(d.radars.size(), 2u);
  const ros1::RosbagRadarSequence direct_bag(bag, d);
  const AutomotiveRunResult direct =
      runAutomotiveOdometry(AutomotiveInputs{direct_bag, direct_bag.vehicleSignals(), direct_bag.problems()},
                            run.automotiveOptions(), makeMatcher(run.automotiveOptions().matcher));
  expectSameTrajectory(entered.estimate, direct.estimate, "bag");
  EXPECT_EQ(entered.prior, "the car's gyro, Doppler translation");
  // What the recording lacks is said, naming the setting as the caller spelled it.
  const std::string text = refusal([&] {
    OdometryRun(RunSource{"rosbag", bag, "", "", "preset:nuscenes_ars408"},
                {{"odometry.car.wheels", FieldValue(true), "--wheels"}});
  });
  EXPECT_NE(text.find("--wheels"), std::string::npos) << text;
  EXPECT_NE(text.find("speed"), std::string::npos) << text;
  EXPECT_NE(refusal([&] {
              OdometryRun(RunSource{"rosbag", bag, "", "", "preset:nuscenes_ars408"},
                          {{"sequence.filter.ambig_states", FieldValue(FieldValue::List{3}), ""}});
            }).find("keep"),
            std::string::npos);
  fs::remove(bag);
}
#endif
