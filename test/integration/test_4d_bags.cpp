// 4D radar bags as other tools write them (part of test_rosbag): NTU4DRadLM's layout, a radar on
// sensor_msgs/PointCloud with channels read by position and an IMU mounted upside down.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud.h>

#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/ros/point_cloud2.h"
#include "radar_ndt/ros/rosbag_sequence.h"

using namespace radar_ndt;
namespace fs = std::filesystem;

namespace {

/// A bag in NTU4DRadLM's layout: 20 Eagle scans at 10 Hz on /radar_enhanced_pcl (channels
/// Doppler, Range, Power: Doppler −1.5 m/s on every point, power 10 + i), and a VectorNav at
/// 100 Hz on /vectornav/imu mounted upside down (z down): at rest it reads −g along its z, and a
/// left turn of the vehicle at 0.2 rad/s reads −0.2 about its z.
std::string writeNtuBag(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / "radar_ndt_4d_bags";
  fs::create_directories(dir);
  const std::string path = (dir / name).string();
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  const double t0 = 1675000000.0;
  for (int k = 0; k < 200; ++k) {
    sensor_msgs::Imu imu;
    imu.header.stamp = ros::Time(t0 + 0.01 * k);
    imu.header.frame_id = "vectornav";
    imu.angular_velocity.z = -0.2;
    imu.linear_acceleration.z = -9.81;
    imu.orientation.w = 1;
    bag.write("/vectornav/imu", imu.header.stamp, imu);
  }
  for (int k = 0; k < 20; ++k) {
    sensor_msgs::PointCloud c;
    c.header.stamp = ros::Time(t0 + 0.05 + 0.1 * k);
    c.header.frame_id = "eagle";
    c.channels.resize(3);
    c.channels[0].name = "Doppler";
    c.channels[1].name = "Range";
    c.channels[2].name = "Power";
    for (int i = 0; i < 30; ++i) {
      geometry_msgs::Point32 p;
      p.x = 5.f + i;
      p.y = 0.3f * static_cast<float>(i % 7) - 1.f;
      p.z = 0.2f * static_cast<float>(i % 3);
      c.points.push_back(p);
      c.channels[0].values.push_back(-1.5f);
      c.channels[1].values.push_back(std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z));
      c.channels[2].values.push_back(10.f + static_cast<float>(i));
    }
    bag.write("/radar_enhanced_pcl", c.header.stamp, c);
  }
  bag.close();
  return path;
}

}  // namespace

TEST(Rosbag4D, NtuLayoutRadarOnPointCloudAndAnUpsideDownImu) {
  const std::string path = writeNtuBag("ntu.bag");
  const ros1::RosbagRadarSequence bag(path, readSensorDescription("preset:ntu4dradlm_eagle"));
  ASSERT_EQ(bag.size(), 20u);
  EXPECT_EQ(bag.stats().unreadable_messages, 0u);
  const RadarCycle c = bag.load(3);
  ASSERT_EQ(c.sweeps.size(), 1u);
  ASSERT_EQ(c.sweeps[0].points.size(), 30u);
  EXPECT_FLOAT_EQ(c.sweeps[0].points[4].doppler, -1.5f);  // channel 0, positive receding as written
  EXPECT_FLOAT_EQ(c.sweeps[0].points[4].power, 14.f);     // channel 2
  // The upside-down IMU: its −0.2 about its own z is the vehicle's left turn, and nothing is said.
  ASSERT_TRUE(bag.vehicleSignals());
  ASSERT_FALSE(bag.vehicleSignals()->yaw_rate.empty());
  EXPECT_NEAR(bag.vehicleSignals()->yaw_rate.values.front(), 0.2, 1e-4);  // the preset's IMU is tilted a little
  for (const std::string& p : bag.problems()) EXPECT_EQ(p.find("imu_mounting"), std::string::npos) << p;
}

TEST(Rosbag4D, AnImuWhoseGravityIsOnAnotherAxisThanDescribedIsSaid) {
  const std::string path = writeNtuBag("ntu_undescribed.bag");
  // The same bag described without the IMU's mounting: gravity reads down, the figures are said.
  const SensorDescription d = parseSensorDescription(
      "imu: /vectornav/imu\nradars:\n  - topic: /radar_enhanced_pcl\n    mounting: {x: 0.3}\n    fields:\n"
      "      doppler: {radial: Doppler, sign: receding}\n      power: Power\n",
      "undescribed.yaml");
  const ros1::RosbagRadarSequence bag(path, d);
  std::string said;
  for (const std::string& p : bag.problems()) said += p + "\n";
  EXPECT_NE(said.find("/vectornav/imu: the accelerometer reads gravity along (0.00, 0.00, -9.81) m/s^2"),
            std::string::npos)
      << said;
  EXPECT_NE(said.find("give 'imu_mounting'"), std::string::npos) << said;
  // Channels by name work as well as by position; the run goes on with the yaw rate as read.
  EXPECT_FLOAT_EQ(bag.load(0).sweeps[0].points[0].power, 10.f);
  EXPECT_NEAR(bag.vehicleSignals()->yaw_rate.values.front(), -0.2, 1e-6);
}

TEST(Rosbag4D, ChannelsByPositionBeyondTheMessageAreAbsent) {
  sensor_msgs::PointCloud c;
  c.points.resize(2);
  c.channels.resize(1);
  c.channels[0].name = "Doppler";
  c.channels[0].values = {-1.f, 2.f};
  const ros1::CloudColumns cols = ros1::readCloudColumns(c, {"#0", "#1", "#99999999999999999999999", "#", "z"});
  EXPECT_EQ(cols.present, (std::vector<char>{1, 0, 0, 0, 1}));
  EXPECT_EQ(cols.table[0], -1.0);
  EXPECT_EQ(cols.table[5], 2.0);
  c.channels[0].values.pop_back();
  EXPECT_THROW(ros1::readCloudColumns(c, {"#0"}), std::invalid_argument);
}
