// The nuScenes writer: a dataroot written with NuScenesTableWriter and writeNuScenesRadarPcd reads
// back through NuScenesDataset and readNuScenesRadarPcd with every value it was given.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/nuscenes_writer.h"
#include "radar_ndt/se2.h"
#include "test_support.h"

using namespace radar_ndt;

TEST(NuScenesWriter, Ars408RmsIndexInvertsTheStateTable) {
  for (int i = 0; i < 31; ++i) EXPECT_EQ(ars408RmsIndex(ars408RmsValue(i)), i);
  EXPECT_EQ(ars408RmsIndex(0.3), 16);  // 0.288 is nearer in log than 0.371
  EXPECT_EQ(ars408RmsIndex(1e-6), 0);
  EXPECT_EQ(ars408RmsIndex(1e6), 30);
}

TEST(NuScenesWriter, ADatarootReadsBackWithEveryValue) {
  namespace fs = std::filesystem;
  const std::string dir = test::freshTempDir("nuscenes_writer");
  fs::create_directories(dir + "/v1.0-test");
  fs::create_directories(dir + "/samples/RADAR_FRONT");

  std::vector<NuScenesRadarPoint> points(2);
  points[0].x = 10.f;
  points[0].y = 0.f;
  points[0].vx = -3.f;  // approaching: Doppler −3 m/s
  points[0].rcs = 5.5f;
  points[0].x_rms = static_cast<std::int8_t>(ars408RmsIndex(0.2));
  points[0].y_rms = static_cast<std::int8_t>(ars408RmsIndex(0.5));
  points[1].x = 0.f;
  points[1].y = 20.f;
  points[1].vy = 2.f;           // receding: +2 m/s
  points[1].invalid_state = 1;  // an invalid cluster: the default filter drops it
  const std::string pcd = "samples/RADAR_FRONT/test__RADAR_FRONT__1000.pcd";
  writeNuScenesRadarPcd(dir + "/" + pcd, points);

  NuScenesTableWriter tables;
  tables.addLog("log0", "a log", "car", "", "here");
  tables.addScene("scene0", "log0", 1, "sample0", "sample0", "scene-test", "written by the test");
  tables.addSample("sample0", 1000, "", "", "scene0");
  tables.addSensor("sensor0", "RADAR_FRONT", "radar");
  const double yaw = 0.3;
  tables.addCalibratedSensor("calib0", "sensor0", {3.4, 0.1, 0.5},
                             {std::cos(0.5 * yaw), 0.0, 0.0, std::sin(0.5 * yaw)});
  tables.addEgoPose("ego0", 1000, {1.0, 0.0, 0.0, 0.0}, {100.0, -50.0, 0.0});
  tables.addSampleData("data0", "sample0", "ego0", "calib0", 1000, true, pcd, "", "");
  tables.write(dir + "/v1.0-test");

  const NuScenesDataset data(dir);
  ASSERT_EQ(data.scenes().size(), 1u);
  EXPECT_EQ(data.scenes()[0].name, "scene-test");
  ASSERT_EQ(data.radarChannels().size(), 1u);
  const auto sweeps = data.radarSweeps(data.scenes()[0]);
  ASSERT_EQ(sweeps.size(), 1u);
  EXPECT_EQ(sweeps[0].timestamp_us, 1000);
  EXPECT_TRUE(sweeps[0].is_key_frame);
  EXPECT_TRUE(toPose2(sweeps[0].sensor_to_ego).isApprox(Pose2(3.4, 0.1, yaw), 1e-12));
  EXPECT_NEAR(sweeps[0].sensor_to_ego.translation().z(), 0.5, 1e-12);
  EXPECT_TRUE(toPose2(sweeps[0].ego_to_global).isApprox(Pose2(100.0, -50.0, 0.0), 1e-12));

  NuScenesPcdStats stats;
  const auto cloud = readNuScenesRadarPcd(sweeps[0].path, NuScenesRadarFilter(), 0, &stats);
  EXPECT_EQ(stats.points_in_file, 2u);
  ASSERT_EQ(cloud.size(), 1u);
  EXPECT_FLOAT_EQ(cloud[0].x, 10.f);
  EXPECT_FLOAT_EQ(cloud[0].doppler, -3.f);
  EXPECT_FLOAT_EQ(cloud[0].rcs, 5.5f);
  EXPECT_NEAR(cloud[0].cov_xx, ars408RmsValue(ars408RmsIndex(0.2)) * ars408RmsValue(ars408RmsIndex(0.2)), 1e-6);
  EXPECT_NEAR(cloud[0].cov_yy, ars408RmsValue(ars408RmsIndex(0.5)) * ars408RmsValue(ars408RmsIndex(0.5)), 1e-6);
  NuScenesRadarFilter all;
  all.invalid_states.clear();
  const auto both = readNuScenesRadarPcd(sweeps[0].path, all, 0);
  ASSERT_EQ(both.size(), 2u);
  EXPECT_FLOAT_EQ(both[1].doppler, 2.f);
}

TEST(NuScenesWriter, AnUnwritablePathIsAnIoErrorNamingIt) {
  EXPECT_THROW(writeNuScenesRadarPcd("/nonexistent_dir/x.pcd", {}), IoError);
  NuScenesTableWriter tables;
  try {
    tables.write("/nonexistent_dir/v1.0-x");
    FAIL() << "expected an IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_dir/v1.0-x/sensor.json"), std::string::npos) << e.what();
  }
}
