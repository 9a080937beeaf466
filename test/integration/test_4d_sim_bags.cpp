// A 4D recording written in each real driver's layout (ros/radar_4d_bag.h, what radar_sim --type 4d
// writes) and read back through the sensor description preset that reads that driver's bags (part
// of test_rosbag): the points, the Doppler's sign, the power or RCS, the IMU's axes and the ground
// truth come back as written; the TI layout is the real driver's, field by field; doppler-imu runs
// on a simulated bag read back as on the simulated sequence.
#include <gtest/gtest.h>

#include <fstream>

#include <cmath>
#include <filesystem>
#include <string>

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>

#include "radar_ndt/evaluation/metrics.h"
#include "radar_ndt/evaluation/metrics_6dof.h"
#include "radar_ndt/evaluation/run_report.h"
#include "radar_ndt/frontend/ego_velocity_3d.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/sensor_description.h"
#include "radar_ndt/odometry/doppler_imu.h"
#include "radar_ndt/pipeline/odometry_run.h"
#include "radar_ndt/ros/bag_reader.h"
#include "radar_ndt/ros/radar_4d_bag.h"
#include "radar_ndt/ros/rosbag_sequence.h"
#include "radar_ndt/sim/motion_6dof.h"

using namespace radar_ndt;
namespace fs = std::filesystem;

namespace {

std::string simBagPath(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / "radar_ndt_4d_sim_bags";
  fs::create_directories(dir);
  return (dir / name).string();
}

/// Six scans at 10 Hz of five detections each (receding and approaching), an IMU at 100 Hz turning
/// left at 0.3 rad/s with gravity up, and the truth driving forward.
ros1::Radar4DRecording recording() {
  ros1::Radar4DRecording r;
  const double t0 = 1609459200.0;
  for (int k = 0; k < 6; ++k) {
    r.stamps.push_back(t0 + 0.05 + 0.1 * k);
    pcl::PointCloud<PointRadar4D> scan;
    for (int i = 0; i < 5; ++i) {
      PointRadar4D p(4.f + static_cast<float>(i), 0.5f * static_cast<float>(i - 2), 0.25f * static_cast<float>(i % 3));
      p.doppler = i % 2 == 0 ? -1.25f - 0.1f * static_cast<float>(k) : 0.75f;
      p.power = 12.f + static_cast<float>(i);
      p.rcs = -3.f + static_cast<float>(i);
      scan.push_back(p);
    }
    r.scans.push_back(scan);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(1.5 * k, 0.1 * k, 0.02 * k);
    T.linear() = Eigen::AngleAxisd(0.03 * k, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    r.truth.stamps.push_back(r.stamps.back());
    r.truth.poses.push_back(T);
  }
  for (int k = 0; k < 70; ++k)
    r.imu.push_back({t0 + 0.01 * k, Eigen::Vector3d(0.01, -0.02, 0.3), Eigen::Vector3d(0.2, 0.1, 9.81)});
  return r;
}

struct Layout {
  const char* preset;
  ros1::Radar4DBagLayout layout;
};

class Radar4DSimBag : public ::testing::TestWithParam<Layout> {};

TEST_P(Radar4DSimBag, IsReadBackThroughItsDriversPresetAsWritten) {
  SensorDescription d = readSensorDescription(std::string("preset:") + GetParam().preset);
  d.ground_truth_topic = "/gt";
  const ros1::Radar4DRecording r = recording();
  const std::string path = simBagPath(std::string(GetParam().preset) + ".bag");
  const ros1::Radar4DBagStats stats = ros1::writeRadar4DBag(path, GetParam().layout, d, r);
  EXPECT_EQ(stats.scans, 6u);
  EXPECT_EQ(stats.imu, 70u);
  EXPECT_EQ(stats.ground_truth, 6u);

  const ros1::RosbagRadarSequence bag(path, d);
  ASSERT_EQ(bag.size(), 6u);
  EXPECT_EQ(bag.stats().unreadable_messages, 0u);
  const Eigen::Isometry3d mounting = d.radars[0].mounting->transform();
  for (std::size_t k = 0; k < bag.size(); ++k) {
    const RadarCycle c = bag.load(k);
    EXPECT_EQ(c.timestamp_us, std::llround(r.stamps[k] * 1e6));
    ASSERT_EQ(c.sweeps.size(), 1u);
    EXPECT_TRUE(c.sweeps[0].sensor_to_vehicle.isApprox(mounting, 1e-12));
    ASSERT_EQ(c.sweeps[0].points.size(), 5u);
    for (std::size_t i = 0; i < 5; ++i) {
      const PointRadar& p = c.sweeps[0].points[i];
      const PointRadar4D& q = r.scans[k][i];
      EXPECT_FLOAT_EQ(p.x, q.x);
      EXPECT_FLOAT_EQ(p.y, q.y);
      EXPECT_FLOAT_EQ(p.z, q.z);
      EXPECT_FLOAT_EQ(p.doppler, q.doppler) << "point " << i << " of scan " << k;  // positive receding again
      if (!d.radars[0].fields.power.empty()) {
        EXPECT_FLOAT_EQ(p.power, q.power);
      }
      if (!d.radars[0].fields.rcs.empty()) {
        EXPECT_FLOAT_EQ(p.rcs, q.rcs);
      }
    }
  }
  // The IMU was written in its described axes: turned back into the base frame, the left turn.
  ASSERT_TRUE(bag.vehicleSignals());
  ASSERT_EQ(bag.vehicleSignals()->yaw_rate.size(), 70u);
  for (double w : bag.vehicleSignals()->yaw_rate.values) EXPECT_NEAR(w, 0.3, 1e-9);
  for (const std::string& p : bag.problems()) EXPECT_EQ(p.find("gravity"), std::string::npos) << p;
  const Trajectory& gt = bag.groundTruthPoses();
  ASSERT_EQ(gt.size(), 6u);
  for (std::size_t k = 0; k < gt.size(); ++k) {
    EXPECT_NEAR(gt.stamps[k], r.truth.stamps[k], 1e-6);
    EXPECT_TRUE(gt.poses[k].isApprox(r.truth.poses[k], 1e-9));
  }
}

INSTANTIATE_TEST_SUITE_P(Drivers, Radar4DSimBag,
                         ::testing::Values(Layout{"ti_iwr6843_rio", ros1::Radar4DBagLayout::TiMmwave},
                                           Layout{"snail_radar_ars548", ros1::Radar4DBagLayout::SnailArs548},
                                           Layout{"ntu4dradlm_eagle", ros1::Radar4DBagLayout::NtuEagle}),
                         [](const auto& info) { return std::string(info.param.preset); });

sensor_msgs::PointCloud2 firstCloud(const std::string& path, const std::string& topic) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag, rosbag::TopicQuery(topic));
  for (const rosbag::MessageInstance& m : view)
    if (auto c = m.instantiate<sensor_msgs::PointCloud2>()) return *c;
  ADD_FAILURE() << "no " << topic << " in " << path;
  return {};
}

TEST(Radar4DSimBag, TheTiLayoutIsTheRealDriversFieldByField) {
  const std::string rio = std::string(RADAR_NDT_SHARED_DATA) + "/ros-rio-ti-mmwave/ti_mmwave_rospkg_demo.bag";
  if (!fs::exists(rio)) GTEST_SKIP() << "no " << rio << " (../shared/data is absent)";
  const SensorDescription d = readSensorDescription("preset:ti_iwr6843_rio");
  const std::string path = simBagPath("ti_layout.bag");
  ros1::writeRadar4DBag(path, ros1::Radar4DBagLayout::TiMmwave, d, recording());
  const sensor_msgs::PointCloud2 real = firstCloud(rio, d.radars[0].topic);
  const sensor_msgs::PointCloud2 ours = firstCloud(path, d.radars[0].topic);
  ASSERT_EQ(ours.fields.size(), real.fields.size());
  for (std::size_t f = 0; f < real.fields.size(); ++f) {
    EXPECT_EQ(ours.fields[f].name, real.fields[f].name);
    EXPECT_EQ(ours.fields[f].offset, real.fields[f].offset);
    EXPECT_EQ(ours.fields[f].datatype, real.fields[f].datatype);
    EXPECT_EQ(ours.fields[f].count, real.fields[f].count);
  }
  EXPECT_EQ(ours.point_step, real.point_step);
  EXPECT_EQ(ours.height, real.height);
  EXPECT_EQ(ours.is_bigendian, real.is_bigendian);
  EXPECT_EQ(ours.header.frame_id, real.header.frame_id);
  EXPECT_EQ(ours.header.stamp, real.header.stamp);  // the driver's zero stamp
}

TEST(Radar4DSimBag, ScansAndStampsThatDisagreeOrPrecede1970AreRefused) {
  const SensorDescription d = readSensorDescription("preset:snail_radar_ars548");
  ros1::Radar4DRecording r = recording();
  r.stamps.pop_back();
  EXPECT_THROW(ros1::writeRadar4DBag(simBagPath("bad.bag"), ros1::Radar4DBagLayout::SnailArs548, d, r),
               std::invalid_argument);
  r = recording();
  r.stamps[0] = -1.0;
  try {
    ros1::writeRadar4DBag(simBagPath("bad.bag"), ros1::Radar4DBagLayout::SnailArs548, d, r);
    ADD_FAILURE() << "a negative time was written";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.bag"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot be a ROS time"), std::string::npos) << e.what();
  }
}

}  // namespace

namespace {

/// A car's drive for the simulator: 10 m/s along x with a left turn, 4 Hz poses.
Trajectory carDrive(double seconds) {
  Trajectory t;
  double yaw = 0;
  Eigen::Vector3d p(0, 0, 0);
  for (double s = 0; s <= seconds; s += 0.25) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = p;
    t.stamps.push_back(1609459200.0 + s);
    t.poses.push_back(T);
    const double rate = (s > 10 && s < 17) ? 0.2 : 0.0;  // a left turn of 80°
    yaw += rate * 0.25;
    p += 2.5 * Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0);
  }
  return t;
}

/// The simulator's Eagle and MEMS IMU along a 30 s drive, written to `path` in NTU4DRadLM's layout
/// (the radar 0.3 m ahead, the IMU upside down) with its truth on /gt; `d` the description that
/// reads it. Returns the drive's length (m) and the IMU messages written.
std::pair<double, std::size_t> writeEagleDrive(const std::string& path, SensorDescription& d) {
  const sim::Motion6Dof motion(carDrive(30));
  d = readSensorDescription("preset:ntu4dradlm_eagle");
  d.ground_truth_topic = "/gt";
  const Eigen::Isometry3d mounting = d.radars[0].mounting->transform();
  const sim::Radar4DSequence seq =
      sim::simulateRadar4DSequence(motion, sim::worldAlongPath(motion, true, 3), sim::radar4DPreset("oculii_eagle"), 10,
                                   sim::imu6Preset("mems"), 5, mounting);
  ros1::Radar4DRecording r;
  r.stamps = seq.stamps;
  r.scans = seq.scans;
  r.imu = seq.imu;
  r.truth = seq.truth;
  ros1::writeRadar4DBag(path, ros1::Radar4DBagLayout::NtuEagle, d, r);
  return {motion.length(), seq.imu.size()};
}

/// doppler-imu as the test below runs it by hand: each scan's body velocity from the IMU's last
/// reading at its time, then the IMU.
DopplerImuResult dopplerImuByHand(const ros1::RosbagRadarSequence& bag, const std::vector<ImuSample>& imu) {
  const EgoVelocity3DEstimator estimator;
  std::vector<BodyVelocitySample> velocities;
  std::size_t i = 0;
  for (std::size_t k = 0; k < bag.size(); ++k) {
    const RadarCycle cycle = bag.load(k);
    const RadarSweepData& sweep = cycle.sweeps.at(0);
    const double t = static_cast<double>(sweep.timestamp_us) * 1e-6;
    while (i + 1 < imu.size() && imu[i + 1].t <= t) ++i;
    const EgoVelocity3D e = estimator.estimate(sweep.points);
    velocities.push_back({t, bodyVelocity(sweep.sensor_to_vehicle, e.velocity, imu[i].gyro), e.valid});
  }
  return runDopplerImu(imu, velocities);
}

}  // namespace

TEST(Radar4DSimBag, DopplerImuRunsOnASimulatedBagAsOnTheSequence) {
  // Each scan's 3D Doppler velocity turned into the body's by the mounting and the IMU's rate,
  // doppler-imu on them and the IMU's 6-axis readings, against the bag's own truth. Read in the
  // wrong axes, it is far off.
  SensorDescription d;
  const std::string path = simBagPath("eagle_drive.bag");
  const auto [length, imu_messages] = writeEagleDrive(path, d);
  const ros1::RosbagRadarSequence bag(path, d);
  ASSERT_EQ(bag.imuSamples().size(), imu_messages);
  EXPECT_NEAR(bag.imuSamples().front().accel.z(), 9.81, 0.2);  // upside down as written, up as read
  auto run = [&](const std::vector<ImuSample>& imu) {
    const DopplerImuResult result = dopplerImuByHand(bag, imu);
    std::string said;
    for (const std::string& p : result.problems) said += p + "\n";
    return std::make_pair(absoluteTrajectoryError6Dof(associate(bag.groundTruthPoses(), result.trajectory),
                                                      TrajectoryAlignment::PositionYaw),
                          said);
  };
  const auto [ate, said] = run(bag.imuSamples());
  EXPECT_EQ(said, "");
  std::printf("doppler-imu on the simulated Eagle bag: ATE posyaw %.3f m, %.3f deg over %.0f m\n", ate.rmse_m,
              ate.rot_rmse_deg, length);
  EXPECT_LT(ate.rmse_m, 1.5) << "over " << length << " m";
  EXPECT_LT(ate.rot_rmse_deg, 1.5);
  // The same readings in the IMU's own axes (upside down: its mounting not applied) are far off.
  std::vector<ImuSample> raw = bag.imuSamples();
  const Eigen::Matrix3d back = imuRotation(d).transpose();
  for (ImuSample& s : raw) {
    s.gyro = back * s.gyro;
    s.accel = back * s.accel;
  }
  const auto [raw_ate, raw_said] = run(raw);
  EXPECT_GT(raw_ate.rmse_m, 3 * ate.rmse_m);
  EXPECT_NE(raw_said.find("check the IMU's axes"), std::string::npos) << raw_said;
}

// The 6-DoF run through the one entry, as radar_odometry --format rosbag --method M [--imu] runs
// it, on the simulated Eagle bag: doppler-imu gives what it gives by hand, pose for pose; the
// odometry, fused and radar only, follows the bag's truth (radar only, its roll and pitch drift); a method without what
// it needs and a setting of the planar pipeline are refused by name.
TEST(Radar4DSimBag, TheSixDofRunReadsASimulatedBag) {
  SensorDescription d;
  const std::string path = simBagPath("eagle_run.bag");
  const double length = writeEagleDrive(path, d).first;
  const std::string sensors = simBagPath("eagle_run.yaml");
  {
    std::ifstream in(sensorPresetDirectory() + "/ntu4dradlm_eagle.yaml");
    std::ofstream out(sensors);
    out << in.rdbuf() << "\nground_truth: /gt\n";
  }
  ros1::registerBagReader();
  const RunSource source{"rosbag", path, "", "", sensors};
  auto runWith = [&](const std::string& method, bool imu) {
    const OdometryRun run(source, {{"matcher.method", FieldValue(method), ""}, {"imu", FieldValue(imu), ""}});
    EXPECT_EQ(run.pipeline(), PipelineKind::Inertial);
    EXPECT_TRUE(run.hasGroundTruth());
    return run.runInertial();
  };
  const InertialRunResult baseline = runWith("doppler-imu", true);
  const ros1::RosbagRadarSequence bag(path, d);
  const DopplerImuResult hand = dopplerImuByHand(bag, bag.imuSamples());
  ASSERT_EQ(baseline.estimate.size(), hand.trajectory.size());
  for (std::size_t i = 0; i < hand.trajectory.size(); ++i)
    ASSERT_LT((baseline.estimate.poses[i].matrix() - hand.trajectory.poses[i].matrix()).norm(), 1e-9) << i;
  for (const bool imu : {true, false}) {
    const InertialRunResult r = runWith("pw-ndt-3d", imu);
    const RunEvaluation e = evaluateRun(r);
    ASSERT_TRUE(e.report.ate_posyaw);
    std::printf("pw-ndt-3d%s on the simulated Eagle bag: %zu poses, %zu fallbacks, ATE posyaw %.3f m, %.3f deg\n",
                imu ? " + IMU" : "", r.estimate.size(), r.fallbacks, e.report.ate_posyaw->rmse_m,
                e.report.ate_posyaw->rot_rmse_deg);
    EXPECT_LT(r.fallbacks, r.scans / 10);
    // Radar only, roll and pitch drift (the Eagle's elevation is coarse, no gravity holds them):
    // its position within 3 % of the drive, the rotation bounded only fused.
    EXPECT_LT(e.report.ate_posyaw->rmse_m, imu ? 1.0 : 0.03 * length);
    if (imu) {
      EXPECT_LT(e.report.ate_posyaw->rot_rmse_deg, 1.0);
    }
  }
  // Each detection's accuracy: the description's spherical_accuracy, the settings given over it.
  const OdometryRun described(source, {{"matcher.method", FieldValue("pw-ndt-3d"), ""}});
  EXPECT_EQ(described.inertialOptions().accuracy.azimuth_sigma_deg, d.radars[0].fields.spherical->azimuth_deg);
  EXPECT_EQ(described.inertialOptions().accuracy.elevation_sigma_deg, 1.0);
  const OdometryRun given(
      source, {{"matcher.method", FieldValue("pw-ndt-3d"), ""}, {"accuracy.elevation_sigma_deg", FieldValue(4.0), ""}});
  EXPECT_EQ(given.inertialOptions().accuracy.elevation_sigma_deg, 4.0);
  EXPECT_EQ(given.inertialOptions().accuracy.azimuth_sigma_deg, d.radars[0].fields.spherical->azimuth_deg);
  EXPECT_THROW(OdometryRun(source, {{"matcher.method", FieldValue("doppler-imu"), ""}}), std::invalid_argument);
  try {
    OdometryRun(source, {{"matcher.method", FieldValue("pw-ndt-3d"), ""}, {"matcher.grid", FieldValue(2.0), ""}});
    ADD_FAILURE() << "a setting of the automotive pipeline was taken";
  } catch (const SettingError& e) {
    EXPECT_NE(std::string(e.what()).find("automotive"), std::string::npos) << e.what();
  }
}
