// The nuScenes CAN bus reader (io/nuscenes_can_bus.h) and the time series it returns
// (core/time_series.h): real files from ../shared/data/nuscenes-mini-radar/can_bus (skipped when
// absent): counts, units, the yaw rate's sign against the ground truth's heading change; and
// malformed files, each a clear error naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/nuscenes_can_bus.h"
#include "radar_ndt/io/nuscenes_sequence.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/time_series.h"
#include "test_support.h"

using namespace radar_ndt;
using test::freshTempDir;
namespace fs = std::filesystem;

namespace {

const std::string kCanBusRoot = std::string(RADAR_NDT_SHARED_DATA) + "/nuscenes-mini-radar";

void write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

/// A dataroot with a can_bus folder holding `imu` and `wheels` as the scene's two messages.
std::string canBusRoot(const std::string& name, const std::string& imu, const std::string& wheels) {
  const std::string root = freshTempDir(name);
  fs::create_directories(root + "/can_bus");
  write(root + "/can_bus/scene-1_ms_imu.json", imu);
  write(root + "/can_bus/scene-1_zoe_veh_info.json", wheels);
  return root;
}

const char* kWheels =
    R"([{"utime": 0, "RL_wheel_speed": 60.0, "RR_wheel_speed": 62.0}, {"utime": 1000000, "RL_wheel_speed": 60.0, "RR_wheel_speed": 62.0}])";

}  // namespace

TEST(TimeSeries, IntegratesTheLinearInterpolationAndHoldsTheEnds) {
  TimeSeries s;
  s.stamps_us = {0, 1000000, 2000000};
  s.values = {0.0, 2.0, 2.0};
  EXPECT_DOUBLE_EQ(s.at(500000), 1.0);
  EXPECT_DOUBLE_EQ(s.integral(0, 1000000), 1.0) << "the trapezoid";
  EXPECT_DOUBLE_EQ(s.integral(500000, 1500000), 0.75 + 1.0);
  EXPECT_DOUBLE_EQ(s.integral(2000000, 3000000), 2.0) << "the last value held beyond the end";
  EXPECT_DOUBLE_EQ(s.integral(1000000, 0), -1.0);
  EXPECT_DOUBLE_EQ(s.mean(1000000, 2000000), 2.0);
  EXPECT_TRUE(s.covers(0, 2000000));
  EXPECT_FALSE(s.covers(0, 2000001));
  EXPECT_DOUBLE_EQ(TimeSeries{}.integral(0, 10), 0.0);
}

TEST(NuScenesCanBus, ReadsTheYawRateAndTheRearWheelsMean) {
  const std::string root = canBusRoot(
      "can_bus_ok", R"([{"utime": 0, "rotation_rate": [0.1, 0.2, 0.5]}, {"utime": 10, "rotation_rate": [0, 0, NaN]}])",
      kWheels);
  const auto s = readNuScenesCanBus(root, "scene-1");
  ASSERT_TRUE(s.has_value());
  ASSERT_EQ(s->yaw_rate.size(), 1u) << "the NaN that Python's json writes is a missing value, left out";
  EXPECT_EQ(s->dropped, 1u);
  EXPECT_DOUBLE_EQ(s->yaw_rate.values[0], 0.5) << "z of rotation_rate";
  ASSERT_EQ(s->rear_wheel_rpm.size(), 2u);
  EXPECT_DOUBLE_EQ(s->rear_wheel_rpm.values[0], 61.0);
}

TEST(NuScenesCanBus, NoFolderIsNothingAndABadFileIsAnErrorNamingIt) {
  EXPECT_FALSE(readNuScenesCanBus(freshTempDir("can_bus_none"), "scene-1").has_value());
  const auto fails = [](const std::string& name, const std::string& imu, const std::string& needle) {
    const std::string root = canBusRoot(name, imu, kWheels);
    try {
      readNuScenesCanBus(root, "scene-1");
      ADD_FAILURE() << name << ": no error";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find("scene-1_ms_imu.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  fails("can_bus_json", R"([{"utime": 0, "rotation_rate": [0, 0,)", "invalid JSON");
  fails("can_bus_object", R"({"utime": 0})", "list of messages");
  fails("can_bus_utime", R"([{"rotation_rate": [0, 0, 1]}])", "'utime'");
  fails("can_bus_key", R"([{"utime": 0, "rate": [0, 0, 1]}])", "'rotation_rate' is missing");
  fails("can_bus_short", R"([{"utime": 0, "rotation_rate": [0, 0]}])", "at least 3");
  fails("can_bus_type", R"([{"utime": 0, "rotation_rate": [0, 0, "x"]}])", "not a number");
  fails("can_bus_back", R"([{"utime": 5, "rotation_rate": [0, 0, 1]}, {"utime": 4, "rotation_rate": [0, 0, 1]}])",
        "back in time");
  const std::string root = freshTempDir("can_bus_missing");
  fs::create_directories(root + "/can_bus");
  write(root + "/can_bus/scene-1_ms_imu.json", R"([{"utime": 0, "rotation_rate": [0, 0, 1]}])");
  EXPECT_THROW(readNuScenesCanBus(root, "scene-1"), IoError) << "the folder is there, a message is not";
}

TEST(NuScenesCanBus, RealFilesCountsUnitsAndTheYawRatesSign) {
  if (!fs::exists(kCanBusRoot + "/can_bus"))
    GTEST_SKIP() << "no " << kCanBusRoot << "/can_bus (../shared/data is absent)";
  const NuScenesDataset dataset(kCanBusRoot);
  for (const auto& scene : dataset.scenes()) {
    const auto s = readNuScenesCanBus(kCanBusRoot, scene.name);
    ASSERT_TRUE(s.has_value()) << scene.name;
    const double span = 1e-6 * static_cast<double>(scene.last_timestamp_us - scene.first_timestamp_us);
    // 100 Hz messages over the scene.
    EXPECT_NEAR(static_cast<double>(s->yaw_rate.size()) / span, 100.0, 10.0) << scene.name;
    EXPECT_NEAR(static_cast<double>(s->rear_wheel_rpm.size()) / span, 100.0, 10.0) << scene.name;
    // The gyro's heading change against the ground truth's: the sign and, within 2 degrees, the size
    // (z up, counter-clockwise positive, rad/s).
    const NuScenesRadarSequence seq(dataset, scene);
    const Trajectory gt = seq.groundTruthTrajectory();
    double gt_turn = 0;
    for (std::size_t i = 1; i < gt.poses.size(); ++i) gt_turn += toPose2(gt.poses[i - 1].inverse() * gt.poses[i]).z();
    const auto t0 = static_cast<std::int64_t>(std::llround(gt.stamps.front() * 1e6));
    const auto t1 = static_cast<std::int64_t>(std::llround(gt.stamps.back() * 1e6));
    const double gyro_turn = s->yaw_rate.integral(t0, t1);
    EXPECT_NEAR(gyro_turn, gt_turn, 2.0 * kPi / 180.0) << scene.name;
    // The rear wheels at the nominal 0.305 m: within 2 % of the ground truth's distance (m/s = rpm × 2π r / 60).
    double gt_distance = 0;
    for (std::size_t i = 1; i < gt.poses.size(); ++i)
      gt_distance += toPose2(gt.poses[i - 1].inverse() * gt.poses[i]).head<2>().norm();
    const double wheel_distance = s->rear_wheel_rpm.integral(t0, t1) / 60.0 * 2.0 * kPi * 0.305;
    EXPECT_NEAR(wheel_distance / gt_distance, 1.0, 0.02) << scene.name;
  }
}
