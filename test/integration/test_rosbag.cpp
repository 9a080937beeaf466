// ROS 1 bags: a nuScenes scene written as a bag and run through the preset gives the scene's own
// trajectory to the last bit; the real rio bag (a TI radar's driver with zero stamps) is read as it
// is; bad bags and bad clouds give errors that say what is wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/nuscenes_can_bus.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/odometry/matcher.h"
#include "radar_ndt/pipeline/automotive_run.h"
#include "radar_ndt/pipeline/scanning_run.h"
#include "radar_ndt/ros/nuscenes_bag.h"
#include "radar_ndt/ros/point_cloud2.h"
#include "radar_ndt/ros/ros_time.h"
#include "radar_ndt/ros/rosbag_scans.h"
#include "radar_ndt/ros/rosbag_sequence.h"
#include "radar_ndt/ros/scan_bag.h"
#include "sanitized_build.h"
#include <geometry_msgs/TwistStamped.h>
#include <sensor_msgs/Image.h>

using namespace radar_ndt;
namespace fs = std::filesystem;

namespace {

const std::string kNuScenes = std::string(RADAR_NDT_SHARED_DATA) + "/nuscenes-mini-radar";
const std::string kRio = std::string(RADAR_NDT_SHARED_DATA) + "/ros-rio-ti-mmwave/ti_mmwave_rospkg_demo.bag";

std::string tempPath(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / "radar_ndt_rosbag";
  fs::create_directories(dir);
  return (dir / name).string();
}

/// Expects an IoError whose message holds every fragment.
template <typename Fn>
void expectIoError(Fn&& fn, const std::vector<std::string>& fragments) {
  try {
    fn();
    ADD_FAILURE() << "expected an IoError holding " << fragments.front();
  } catch (const IoError& e) {
    for (const auto& f : fragments) EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
  }
}

/// A cloud with float32 fields x y z velocity, one point a row of `values`.
sensor_msgs::PointCloud2 cloudOf(const std::vector<std::array<float, 4>>& values, bool big_endian = false) {
  sensor_msgs::PointCloud2 c;
  const char* names[] = {"x", "y", "z", "velocity"};
  for (std::uint32_t i = 0; i < 4; ++i) {
    sensor_msgs::PointField f;
    f.name = names[i];
    f.offset = 4 * i;
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    c.fields.push_back(f);
  }
  c.height = 1;
  c.width = static_cast<std::uint32_t>(values.size());
  c.point_step = 16;
  c.row_step = 16 * c.width;
  c.is_bigendian = big_endian;
  c.data.resize(c.row_step);
  for (std::size_t i = 0; i < values.size(); ++i)
    for (std::size_t k = 0; k < 4; ++k) {
      std::uint8_t b[4];
      std::memcpy(b, &values[i][k], 4);
      if (big_endian) std::reverse(b, b + 4);
      std::memcpy(&c.data[16 * i + 4 * k], b, 4);
    }
  return c;
}

const char* const kOneRadar = R"(
radars:
  - name: front
    topic: /front
    mounting: {x: 3.6}
    fields: {doppler: {radial: velocity}}
)";

/// A bag of `n` clouds on /front, 10 Hz, made by `make(i)`.
std::string writeBag(const std::string& name, std::size_t n,
                     const std::function<sensor_msgs::PointCloud2(std::size_t)>& make) {
  const std::string path = tempPath(name);
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  for (std::size_t i = 0; i < n; ++i) {
    sensor_msgs::PointCloud2 c = make(i);
    c.header.stamp = ros::Time(100.0 + 0.1 * static_cast<double>(i));
    bag.write("/front", c.header.stamp, c);
  }
  bag.close();
  return path;
}

}  // namespace

// Done when: `--format rosbag` on a bag written from each shared scene gives the same trajectory as
// `--format nuscenes` on the scene, bit for bit (here through the library, every scene, with and
// without the car's gyro; compressed chunks too).
TEST(Rosbag, ASceneWrittenAsABagRunsToTheScenesTrajectoryBitForBit) {
  if (!fs::exists(kNuScenes)) GTEST_SKIP() << "no " << kNuScenes << " (../shared/data is absent)";
  const NuScenesDataset dataset(kNuScenes);
  const SensorDescription preset = readSensorDescription("preset:nuscenes_ars408");
  // Under the sanitizer, the first two scenes: one LZ4-compressed bag and one plain (sanitized_build.h).
  std::vector<NuScenesScene> scenes = dataset.scenes();
  if (test::kSanitizedBuild && scenes.size() > 2) scenes.resize(2);
  for (const NuScenesScene& scene : scenes) {
    const bool compressed = scene.name == scenes.front().name;
    const std::string path = tempPath(scene.name + ".bag");
    ros1::writeNuScenesBag(dataset, scene, path, compressed ? ros1::BagCompression::Lz4 : ros1::BagCompression::None);
    const ros1::RosbagRadarSequence bag(path, preset);
    const NuScenesRadarSequence direct(dataset, scene);
    EXPECT_EQ(bag.size(), direct.size());
    EXPECT_EQ(bag.referenceChannel(), direct.referenceChannel());
    for (const bool gyro : {false, true}) {
      AutomotiveRunOptions options;
      options.threads = 1;
      options.odometry.car.gyro = gyro;
      const AutomotiveRunResult from_scene = runAutomotiveOdometry(dataset, scene, options);
      const AutomotiveRunResult from_bag = runAutomotiveOdometry(
          AutomotiveInputs{bag, gyro ? bag.vehicleSignals() : nullptr, {}}, options, makeMatcher(options.matcher));
      ASSERT_EQ(from_bag.estimate.size(), from_scene.estimate.size()) << scene.name;
      for (std::size_t k = 0; k < from_bag.estimate.size(); ++k) {
        ASSERT_EQ(from_bag.estimate.stamps[k], from_scene.estimate.stamps[k]) << scene.name << " " << k;
        ASSERT_TRUE(from_bag.estimate.poses[k].matrix() == from_scene.estimate.poses[k].matrix())
            << scene.name << " cycle " << k << (gyro ? " with the gyro" : "");
      }
      // The ground truth from /tf is the scene's ego poses.
      ASSERT_EQ(from_bag.ground_truth.size(), from_scene.ground_truth.size());
      for (std::size_t k = 0; k < from_bag.ground_truth.size(); ++k)
        ASSERT_TRUE(from_bag.ground_truth.poses[k].matrix() == from_scene.ground_truth.poses[k].matrix());
    }
  }
}

// The real bag of a TI IWR6843 driver (ti_mmwave_rospkg 3.3.0): zero header stamps and no frame id,
// x y z intensity velocity as float32, an IMU at about 200 Hz.
TEST(Rosbag, TheRealRioBagIsReadAsTheDriverWroteIt) {
  if (!fs::exists(kRio)) GTEST_SKIP() << "no " << kRio << " (../shared/data is absent)";
  // The preset reads every topic at its receive time (the IMU's header stamps are on another clock);
  // read by the auto rule here, the scans' zero stamps are said.
  SensorDescription d = readSensorDescription("preset:ti_iwr6843_rio");
  EXPECT_EQ(d.stamps, StampSource::Receive);
  d.stamps = StampSource::Auto;
  const ros1::RosbagRadarSequence bag(kRio, d);
  EXPECT_EQ(bag.stats().radar_messages, 412u);
  EXPECT_EQ(bag.stats().unreadable_messages, 0u);
  EXPECT_EQ(bag.stats().imu_messages, 8270u);
  EXPECT_EQ(bag.size(), 412u);  // one radar: a cycle a scan
  EXPECT_NEAR(bag.periodSeconds(), 0.1, 0.01);
  // The zero stamps: the receive times, said once.
  ASSERT_FALSE(bag.problems().empty());
  EXPECT_NE(bag.problems()[0].find("header stamps are 0"), std::string::npos) << bag.problems()[0];
  EXPECT_GT(bag.timestamp(0), 1632233878000000);  // 2021-09-21, not 1970
  std::size_t points = 0;
  for (std::size_t k = 0; k < bag.size(); ++k) {
    const RadarCycle c = bag.load(k);
    ASSERT_EQ(c.sweeps.size(), 1u);
    for (const PointRadar& p : c.sweeps[0].points) {
      EXPECT_LE(std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z), 20.0f);
      EXPECT_TRUE(std::isfinite(p.doppler));
    }
    points += c.sweeps[0].points.size();
  }
  EXPECT_GT(points, 412u * 20);  // 30-50 points a scan
  ASSERT_TRUE(bag.vehicleSignals());
  EXPECT_EQ(bag.vehicleSignals()->yaw_rate.size(), 8270u);
  EXPECT_TRUE(bag.groundTruthTrajectory().empty());  // no ground truth in this recording
}

TEST(Rosbag, CloudFieldsAreReadByNameInEitherByteOrder) {
  for (const bool big : {false, true}) {
    const auto c = cloudOf({{1, 2, 3, -0.5f}, {4, 5, 6, 0.25f}}, big);
    const ros1::CloudColumns cols = ros1::readCloudColumns(c, {"velocity", "x", "nope"});
    ASSERT_EQ(cols.points, 2u);
    EXPECT_EQ(cols.present, (std::vector<char>{1, 1, 0}));
    EXPECT_EQ(cols.table[0], -0.5);
    EXPECT_EQ(cols.table[1], 1.0);
    EXPECT_TRUE(std::isnan(cols.table[2]));
    EXPECT_EQ(cols.table[3], 0.25);
    EXPECT_EQ(cols.table[4], 4.0);
  }
  auto truncated = cloudOf({{1, 2, 3, 4}});
  truncated.data.resize(10);
  EXPECT_THROW(ros1::readCloudColumns(truncated, {"x"}), std::invalid_argument);
  auto beyond = cloudOf({{1, 2, 3, 4}});
  beyond.fields[3].offset = 14;
  EXPECT_THROW(ros1::readCloudColumns(beyond, {"velocity"}), std::invalid_argument);
}

TEST(Rosbag, BadBagsSayWhatIsWrong) {
  const SensorDescription one = parseSensorDescription(kOneRadar, "one.yaml");
  expectIoError([&] { ros1::RosbagRadarSequence(tempPath("no_such.bag"), one); }, {"no_such.bag", "no such bag"});
  // Not a bag at all.
  const std::string text = tempPath("text.bag");
  std::ofstream(text) << "not a bag\n";
  expectIoError([&] { ros1::RosbagRadarSequence(text, one); }, {"text.bag", "not a readable ROS 1 bag"});
  // A recording cut off: no index at its end.
  const std::string good = writeBag("good.bag", 30, [](std::size_t i) {
    return cloudOf({{10, 0, 0, -1}, {0, 10, 0, 0}, {-10, 1, 0, 1}, {5, 5, 0, float(i % 3)}});
  });
  const std::string cut = tempPath("cut.bag");
  fs::copy_file(good, cut, fs::copy_options::overwrite_existing);
  fs::resize_file(cut, fs::file_size(good) * 2 / 3);
  expectIoError([&] { ros1::RosbagRadarSequence(cut, one); }, {"cut.bag", "rosbag reindex"});
  // A topic the description names that the bag lacks, and a topic of the wrong type.
  SensorDescription other = one;
  other.radars[0].topic = "/rear";
  expectIoError([&] { ros1::RosbagRadarSequence(good, other); }, {"/rear", "not in the bag", "/front"});
  SensorDescription imu = one;
  imu.imu_topic = "/front";
  expectIoError([&] { ros1::RosbagRadarSequence(good, imu); }, {"imu topic /front", "sensor_msgs/PointCloud2"});
  // Fields the description names that no cloud has.
  SensorDescription fields = one;
  fields.radars[0].fields.radial = "doppler";
  expectIoError([&] { ros1::RosbagRadarSequence(good, fields); }, {"no field 'doppler'", "x, y, z, velocity"});
  // Without a mounting and with clouds that name no frame.
  SensorDescription unmounted = one;
  unmounted.radars[0].mounting.reset();
  expectIoError([&] { ros1::RosbagRadarSequence(good, unmounted); }, {"no mounting"});
  // The good bag reads.
  const ros1::RosbagRadarSequence ok(good, one);
  EXPECT_EQ(ok.size(), 30u);
}

// One bad frame is said and left out; the run goes on. NaN points are dropped and counted.
TEST(Rosbag, ABadCloudOrNaNPointsAreSaidAndTheRunGoesOn) {
  const std::string path = writeBag("mixed.bag", 20, [](std::size_t i) {
    if (i == 5) {  // a malformed cloud: data shorter than its points
      auto c = cloudOf({{1, 2, 3, 4}, {1, 2, 3, 4}});
      c.data.resize(20);
      return c;
    }
    return cloudOf({{10, 0, 0, -1}, {0, 10, 0, 0}, {NAN, 1, 0, 1}, {5, 5, 0, 0.5f}});
  });
  const ros1::RosbagRadarSequence bag(path, parseSensorDescription(kOneRadar, "one.yaml"));
  EXPECT_EQ(bag.size(), 19u);
  EXPECT_EQ(bag.stats().unreadable_messages, 1u);
  EXPECT_EQ(bag.stats().non_finite_dropped, 19u);
  bool said = false;
  for (const auto& p : bag.problems())
    said = said || (p.find("/front at 100.5") != std::string::npos && p.find("truncated") != std::string::npos);
  EXPECT_TRUE(said) << "the malformed cloud is named with its time";
  std::vector<std::string> problems;
  const RadarCycle c = bag.load(0, &problems);
  EXPECT_EQ(c.sweeps.at(0).points.size(), 3u);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("NaN"), std::string::npos);
}

// A scanning radar's bag: the shared RADIATE scans written in CFEAR's image layout and read with
// RADIATE's own convention run to the folder's trajectory bit for bit; the Oxford scans with the
// navtech_oxford preset give the folder's powers and angles (the rows' recorded times are not in
// the message, so the trajectories differ by the motion compensation alone).
TEST(RosbagScans, ScansWrittenAsABagRunAsTheirFolder) {
  const std::string radiate = std::string(RADAR_NDT_SHARED_DATA) + "/radiate-tiny-foggy";
  const std::string oxford = std::string(RADAR_NDT_SHARED_DATA) + "/oxford-radar-real";
  if (!fs::exists(radiate) || !fs::exists(oxford)) GTEST_SKIP() << "../shared/data is absent";
  {
    const ScanningSequence folder(radiate, ScanFormat::Radiate);
    const std::string bag_path = tempPath("radiate.bag");
    EXPECT_EQ(ros1::writeScanBag(folder, bag_path, ros1::BagCompression::Lz4).scans, folder.size());
    const SensorDescription d = parseSensorDescription(
        "radars:\n  - topic: /Navtech/Polar\n    kind: scanning\n    polar: {rows: azimuth, range_resolution: "
        "0.173611, range_offset_bins: 0, clockwise: true, stamp: start, sweep_period: 0.25}\n",
        "radiate.yaml");
    const ros1::RosbagScanSequence bag(bag_path, d);
    ASSERT_EQ(bag.size(), folder.size());
    ScanningRunOptions o;
    o.threads = 2;
    const ScanningRunResult a = runScanningOdometry(bag, o), b = runScanningOdometry(folder, o);
    EXPECT_EQ(a.format, "rosbag");
    ASSERT_EQ(a.estimate.size(), b.estimate.size());
    for (std::size_t i = 0; i < a.estimate.size(); ++i) {
      EXPECT_EQ(a.estimate.stamps[i], b.estimate.stamps[i]);
      EXPECT_TRUE(a.estimate.poses[i].matrix() == b.estimate.poses[i].matrix()) << "pose " << i;
    }
  }
  const ScanningSequence folder(oxford, ScanFormat::Oxford);
  const std::string bag_path = tempPath("oxford.bag");
  ros1::writeScanBag(folder, bag_path);
  const ros1::RosbagScanSequence bag(bag_path, readSensorDescription("preset:navtech_oxford"));
  ASSERT_EQ(bag.size(), folder.size());
  EXPECT_EQ(bag.groundTruth().size(), folder.groundTruth().size()) << "the ground truth on /gt";
  for (std::size_t k : {std::size_t{0}, folder.size() - 1}) {
    const PolarScan x = bag.load(k), y = folder.load(k);
    EXPECT_EQ(x.stamp, y.stamp);
    EXPECT_EQ(x.power, y.power);
    ASSERT_EQ(x.angle.size(), y.angle.size());
    for (std::size_t a = 0; a < x.angle.size(); ++a) EXPECT_NEAR(x.angle[a], y.angle[a], 1e-12) << a;
    EXPECT_NEAR(static_cast<double>(x.stamp_us.back() - y.stamp_us.back()), 0.0, 5000.0);
  }
  const ScanningRunResult a = runScanningOdometry(bag, {}), b = runScanningOdometry(folder, {});
  ASSERT_EQ(a.estimate.size(), b.estimate.size());
  EXPECT_LT((a.estimate.poses.back().translation() - b.estimate.poses.back().translation()).norm(), 0.05);
  std::string why;
  EXPECT_FALSE(bag.gyro(&why));
  EXPECT_NE(why.find("no imu topic"), std::string::npos) << why;
}

// Polar images that are not what the description says are said and left out; the run goes on.
TEST(RosbagScans, BadImagesAreSaidAndLeftOut) {
  const std::string path = tempPath("bad_scans.bag");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    for (int k = 0; k < 6; ++k) {
      sensor_msgs::Image im;
      im.header.stamp = ros::Time(100 + k / 4.0);
      im.height = 40;  // azimuths, as columns here: rows are ranges
      im.width = 16;
      im.step = 16;
      im.encoding = k == 2 ? "mono16" : "mono8";
      im.data.resize(k == 4 ? 10 : im.step * im.height, 0);
      for (std::size_t i = 0; i < im.data.size(); ++i) im.data[i] = static_cast<std::uint8_t>(i % 251);
      bag.write("/radar/polar", im.header.stamp, im);
    }
  }
  const SensorDescription d = parseSensorDescription(
      "radars:\n  - topic: /radar/polar\n    kind: scanning\n    polar: {rows: range, range_resolution: 0.5, "
      "stamp: end}\n",
      "mine.yaml");
  const ros1::RosbagScanSequence bag(path, d);
  EXPECT_EQ(bag.size(), 4u);
  EXPECT_EQ(bag.stats().unreadable_messages, 2u);
  std::string problems;
  for (const auto& p : bag.indexProblems()) problems += p + "\n";
  EXPECT_NE(problems.find("mono16"), std::string::npos) << problems;
  EXPECT_NE(problems.find("shorter"), std::string::npos) << problems;
  // A column an azimuth: bin b of azimuth a is the image's (b, a); the stamp is the sweep's end.
  const PolarScan scan = bag.load(0);
  EXPECT_EQ(scan.azimuths, 16);
  EXPECT_EQ(scan.bins, 40);
  EXPECT_EQ(scan.row(3)[5], static_cast<std::uint8_t>((5 * 16 + 3) % 251));
  EXPECT_EQ(scan.stamp_us.back(), scan.stamp);
  EXPECT_LT(scan.stamp_us.front(), scan.stamp);
  // A description of point-cloud radars, or an image topic read as clouds, is refused by name.
  expectIoError([&] { ros1::RosbagScanSequence(path, readSensorDescription("preset:nuscenes_ars408")); },
                {"one radar of kind scanning"});
  expectIoError(
      [&] {
        ros1::RosbagRadarSequence(path, parseSensorDescription("radars:\n  - topic: /radar/polar\n    kind: scanning\n"
                                                               "    polar: {rows: range, range_resolution: 0.5}\n",
                                                               "mine.yaml"));
      },
      {"scanning radar"});
}

// A car's speed topic (geometry_msgs/TwistStamped, m/s) is what --wheels fuses from a bag: a
// scene's bag with its rear wheels' speed added as such a topic runs, with the wheels and the gyro,
// to the scene's own wheel-and-gyro trajectory (the same integral in m/s, not rpm: equal to
// rounding).
TEST(Rosbag, ASpeedTopicIsWhatTheWheelsFuse) {
  if (!fs::exists(kNuScenes)) GTEST_SKIP() << "no " << kNuScenes << " (../shared/data is absent)";
  const NuScenesDataset dataset(kNuScenes);
  const NuScenesScene& scene = dataset.scenes()[1];
  const std::string path = tempPath("speed.bag");
  ros1::writeNuScenesBag(dataset, scene, path);
  AutomotiveRunOptions options;
  options.threads = 1;
  options.odometry.car.gyro = options.odometry.car.wheels = true;
  const std::optional<VehicleSignals> can = readNuScenesCanBus(kNuScenes, scene.name);
  ASSERT_TRUE(can && !can->rear_wheel_rpm.empty());
  {
    rosbag::Bag bag(path, rosbag::bagmode::Append);
    for (std::size_t i = 0; i < can->rear_wheel_rpm.size(); ++i) {
      geometry_msgs::TwistStamped t;
      t.header.stamp = ros1::rosTime(can->rear_wheel_rpm.stamps_us[i]);
      t.twist.linear.x =
          can->rear_wheel_rpm.values[i] / 60.0 * 2.0 * std::acos(-1.0) * options.odometry.car.wheel_radius;
      bag.write("/vehicle/twist", t.header.stamp, t);
    }
  }
  SensorDescription d = readSensorDescription("preset:nuscenes_ars408");
  d.speed_topic = "/vehicle/twist";
  const ros1::RosbagRadarSequence bag(path, d);
  ASSERT_TRUE(bag.vehicleSignals());
  EXPECT_EQ(bag.vehicleSignals()->speed.size(), can->rear_wheel_rpm.size());
  const AutomotiveRunResult from_scene = runAutomotiveOdometry(dataset, scene, options);
  const AutomotiveRunResult from_bag =
      runAutomotiveOdometry(AutomotiveInputs{bag, bag.vehicleSignals(), {}}, options, makeMatcher(options.matcher));
  ASSERT_EQ(from_bag.estimate.size(), from_scene.estimate.size());
  for (std::size_t k = 0; k < from_bag.estimate.size(); ++k)
    ASSERT_LT((from_bag.estimate.poses[k].translation() - from_scene.estimate.poses[k].translation()).norm(), 1e-6)
        << k;
  // Without the speed, the wheels' prior differs: the topic is what was used.
  AutomotiveRunOptions gyro_only = options;
  gyro_only.odometry.car.wheels = false;
  const AutomotiveRunResult no_wheels = runAutomotiveOdometry(dataset, scene, gyro_only);
  EXPECT_GT((no_wheels.estimate.poses.back().translation() - from_bag.estimate.poses.back().translation()).norm(),
            1e-4);
  d.speed_topic = "/imu";  // a topic of another type
  expectIoError([&] { ros1::RosbagRadarSequence(path, d); }, {"speed topic /imu carries sensor_msgs/Imu"});
}
