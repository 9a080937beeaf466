// A yaw-rate gyro in the scanning pipeline: Boreas's IMU file read as the dataset documents it,
// the simulator's gyro (its sign, its integral, its noise), the yaw filter's bias estimate and
// gate, and the scanning runs with and without it.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "radar_ndt/evaluation/metrics.h"
#include "radar_ndt/io/boreas_imu.h"
#include "radar_ndt/io/boreas_scan.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/odometry/gyro_yaw.h"
#include "radar_ndt/pipeline/scanning_run.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/imu_model.h"
#include "radar_ndt/sim/radar_sim.h"
#include "test_support.h"

using namespace radar_ndt;
using test::freshTempDir;

namespace {

void writeText(const std::string& path, const std::string& text) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path) << text;
}

std::string errorOf(const std::string& path) {
  try {
    readBoreasImuFile(path);
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// The released layout: GPSTime (ns here), then z, y, x rates and z, y, x accelerations.
TEST(BoreasImu, ReadsTheDocumentedColumnsInTheirOrder) {
  const std::string dir = freshTempDir("boreas_imu_read");
  writeText(dir + "/applanix/imu.csv",
            "GPSTime,angvel_z,angvel_y,angvel_x,accelz,accely,accelx\n"
            "1628184886551599081,0.1,0.2,0.3,0.4,0.5,0.6\n"
            "1628184886556599081,-0.1,0,0,0,0,0\n");
  const auto rows = readBoreasImuFile(dir + "/applanix/imu.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].stamp_us, 1628184886551599);
  EXPECT_DOUBLE_EQ(rows[0].angular_velocity.z(), 0.1);
  EXPECT_DOUBLE_EQ(rows[0].angular_velocity.x(), 0.3);
  EXPECT_DOUBLE_EQ(rows[0].acceleration.y(), 0.5);
  const auto signals = readBoreasImu(dir);
  ASSERT_TRUE(signals.has_value());
  EXPECT_EQ(signals->yaw_rate.values, (std::vector<double>{0.1, -0.1}));
  EXPECT_TRUE(signals->rear_wheel_rpm.empty());
  EXPECT_FALSE(readBoreasImu(dir + "/nowhere").has_value());  // no file: no signals, no error
}

TEST(BoreasImu, WriterAndReaderAgreeWithTheLayout) {
  const std::string path = freshTempDir("boreas_imu_roundtrip") + "/imu.csv";
  std::vector<BoreasImuRow> rows(3);
  for (int i = 0; i < 3; ++i) {
    rows[i].stamp_us = 1628184886000000 + 5000 * i;
    rows[i].angular_velocity = {0.01 * i, 0.02, 0.03 * i};
    rows[i].acceleration = {1, 2, 3};
  }
  writeBoreasImu(path, rows);
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "GPSTime,angvel_z,angvel_y,angvel_x,accelz,accely,accelx");
  const auto back = readBoreasImuFile(path);
  ASSERT_EQ(back.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(back[i].stamp_us, rows[i].stamp_us);
    EXPECT_EQ(back[i].angular_velocity, rows[i].angular_velocity);
    EXPECT_EQ(back[i].acceleration, rows[i].acceleration);
  }
}

TEST(BoreasImu, BadFilesNameTheFileAndTheProblem) {
  const std::string dir = freshTempDir("boreas_imu_bad");
  writeText(dir + "/no_z.csv", "GPSTime,angvel_y,angvel_x\n1,0,0\n2,0,0\n");
  EXPECT_NE(errorOf(dir + "/no_z.csv").find("no column 'angvel_z'"), std::string::npos);
  writeText(dir + "/nan.csv",
            "GPSTime,angvel_z,angvel_y,angvel_x,accelz,accely,accelx\n1628184886551599,nan,0,0,0,0,0\n");
  EXPECT_NE(errorOf(dir + "/nan.csv").find("nan.csv:2"), std::string::npos);
  writeText(dir + "/back.csv",
            "GPSTime,angvel_z,angvel_y,angvel_x,accelz,accely,accelx\n1628184886551599,0,0,0,0,0,0\n"
            "1628184886551599,0,0,0,0,0,0\n");
  EXPECT_NE(errorOf(dir + "/back.csv").find("does not come after"), std::string::npos);
  writeText(dir + "/short.csv", "GPSTime,angvel_z,angvel_y,angvel_x,accelz,accely,accelx\n1628184886551599,0,0\n");
  EXPECT_NE(errorOf(dir + "/short.csv").find("expected 7 columns"), std::string::npos);
  writeText(dir + "/empty.csv", "");
  EXPECT_NE(errorOf(dir + "/empty.csv").find("empty"), std::string::npos);
  EXPECT_NE(errorOf(dir + "/missing.csv").find("missing.csv"), std::string::npos);
}

// The simulated gyro: z up, counter-clockwise positive (the built-in drive turns left from 20 s
// and right from 39 s), its integral the trajectory's heading change within its noise.
TEST(SimImu, IntegratesToTheHeadingChangeWithTheRightSign) {
  const sim::SimTrajectory ego = sim::builtinDrive(60.0);
  const std::int64_t stamp0 = 1628185286000000;
  const auto rows = sim::simulateImu(ego, 0.0, 60.0, 0.0, stamp0, sim::imuPreset(sim::ImuGrade::Navigation), 3);
  TimeSeries z;
  for (const auto& r : rows) {
    z.stamps_us.push_back(r.stamp_us);
    z.values.push_back(r.angular_velocity.z());
  }
  EXPECT_NEAR(rows[1].stamp_us - rows[0].stamp_us, 5000, 1);  // 200 Hz
  for (const auto& [t0, t1] : {std::pair<double, double>{18, 29}, {37, 46}, {0, 60}}) {
    const double truth = normalizeAngle(ego.at(t1).z() - ego.at(t0).z());
    const double gyro = z.integral(stamp0 + std::llround(t0 * 1e6), stamp0 + std::llround(t1 * 1e6));
    EXPECT_NEAR(gyro, truth, 0.01) << t0 << " .. " << t1;
  }
  EXPECT_GT(z.integral(stamp0 + 18000000, stamp0 + 29000000), 1.0);   // left
  EXPECT_LT(z.integral(stamp0 + 37000000, stamp0 + 46000000), -0.5);  // right
}

// The MEMS preset's white noise has the datasheet's density: its samples' spread is
// noise_density · √rate on a straight, and its bias is drawn (not zero).
TEST(SimImu, MemsNoiseHasTheDensityOfItsSettings) {
  const sim::SimTrajectory ego = sim::builtinDrive(20.0);  // straight for the first 20 s
  sim::ImuOptions o = sim::imuPreset(sim::ImuGrade::Mems);
  o.bias_instability = 0;
  const auto rows = sim::simulateImu(ego, 0.5, 19.5, 0.0, 0, o, 7);
  std::vector<double> z;
  for (const auto& r : rows) z.push_back(r.angular_velocity.z());
  const double mean = std::accumulate(z.begin(), z.end(), 0.0) / z.size();
  double var = 0;
  for (double v : z) var += (v - mean) * (v - mean);
  const double sd = std::sqrt(var / (z.size() - 1));
  EXPECT_NEAR(sd, o.noise_density * std::sqrt(o.rate), 0.05 * o.noise_density * std::sqrt(o.rate));
  EXPECT_GT(std::abs(mean), 1e-4);  // the turn-on bias
}

// The filter recovers a gyro bias from matches alone, and a match far from the gyro's yaw is not
// fused.
TEST(GyroYaw, RecoversTheBiasFromMatches) {
  GyroOptions o;
  o.enabled = true;
  GyroYaw f(o);
  const double bias = 0.01, dt = 0.25;
  std::mt19937 rng(5);
  std::normal_distribution<double> match_noise(0.0, o.match_yaw_sigma);
  for (int k = 0; k < 400; ++k) {
    const double truth = 0.05 * std::sin(0.05 * k);
    f.predict(truth + bias * dt, dt);
    f.update(truth + match_noise(rng));
  }
  EXPECT_NEAR(f.bias(), bias, 0.001);
  const double predicted = f.predict(0.1 + bias * dt, dt);
  EXPECT_NEAR(predicted, 0.1, 0.001);
  bool fused = true;
  EXPECT_DOUBLE_EQ(f.update(0.1 + 0.2, &fused), predicted);  // 0.2 rad off: a wrong match
  EXPECT_FALSE(fused);
}

namespace {

/// A simulated Boreas sequence through the left turn of the built-in drive, with a gyro.
std::string turnSequence(const std::string& name, sim::ImuGrade grade) {
  const std::string dir = freshTempDir(name);
  const sim::SimTrajectory ego = sim::builtinDrive(40.0);
  sim::WorldOptions world;
  sim::ScanningOptions scanning;
  sim::applyProfile(sim::ScanningProfile::Oxford, world, scanning);
  scanning.range_resolution = kBoreasBinBeforeUpgrade;
  scanning.bins = 1200;
  sim::SequenceOptions seq;
  seq.start = 72;  // 18 s: the left turn from 20 s on
  seq.frames = 40;
  seq.start_stamp_us = 1628185286000000;
  seq.progress = false;
  sim::BoreasLayoutOptions layout;
  layout.imu = grade != sim::ImuGrade::None;
  layout.imu_options = sim::imuPreset(grade);
  sim::writeBoreasSequence(dir, ego, world, scanning, seq, layout);
  return dir;
}

ScanningRunResult runTurn(const std::string& dir, bool gyro, double time_offset = 0.0) {
  ScanningRunOptions o;
  o.threads = 1;
  o.odometry.gyro.enabled = gyro;
  o.odometry.gyro.time_offset = time_offset;
  return runScanningOdometry(ScanningSequence(dir, ScanFormat::Boreas), o);
}

double rotationError(const ScanningRunResult& r) {
  return frameError(associate(r.ground_truth, r.estimate)).rot_err_deg;
}

}  // namespace

// Through a turn, the navigation-grade gyro's rotation makes the frame-to-frame rotation error
// smaller than the matches' own; the prior says where it came from.
TEST(ScanningGyro, ANavigationGyroCutsTheRotationErrorInATurn) {
  const std::string dir = turnSequence("gyro_turn", sim::ImuGrade::Navigation);
  const ScanningRunResult radar = runTurn(dir, false), fused = runTurn(dir, true);
  EXPECT_EQ(radar.prior, "constant velocity");
  EXPECT_EQ(fused.prior, "constant velocity, gyro yaw");
  const double without = rotationError(radar), with = rotationError(fused);
  EXPECT_LT(with, 0.7 * without) << "with " << with << " deg, without " << without << " deg";
  const FrameError t_without = frameError(associate(radar.ground_truth, radar.estimate));
  const FrameError t_with = frameError(associate(fused.ground_truth, fused.estimate));
  EXPECT_LT(t_with.trans_err_m, 1.5 * t_without.trans_err_m);

  // The gyro on its own clock: stamps 0.3 s late and the offset set gives the same run.
  const std::string path = dir + "/applanix/imu.csv";
  auto rows = readBoreasImuFile(path);
  for (auto& r : rows) r.stamp_us += 300000;
  writeBoreasImu(path, rows);
  const ScanningRunResult shifted = runTurn(dir, true, 0.3);
  ASSERT_EQ(shifted.estimate.size(), fused.estimate.size());
  for (std::size_t k = 0; k < fused.estimate.size(); ++k)
    EXPECT_TRUE(shifted.estimate.poses[k].isApprox(fused.estimate.poses[k], 1e-9)) << k;
}

// --imu on a sequence without a gyro file: the run goes on, says so once, and is the radar-only run.
TEST(ScanningGyro, NoGyroFileIsSaidOnceAndChangesNothing) {
  const std::string dir = turnSequence("gyro_none", sim::ImuGrade::None);
  const ScanningRunResult radar = runTurn(dir, false), asked = runTurn(dir, true);
  int said = 0;
  for (const auto& p : asked.problems) said += p.find("imu.csv: missing") != std::string::npos;
  EXPECT_EQ(said, 1);
  EXPECT_EQ(asked.prior, "constant velocity");
  ASSERT_EQ(asked.estimate.size(), radar.estimate.size());
  for (std::size_t k = 0; k < radar.estimate.size(); ++k)
    EXPECT_TRUE(asked.estimate.poses[k].isApprox(radar.estimate.poses[k], 0.0)) << k;
}

// The simulator's CAN bus (automotive layout) is what the nuScenes reader reads: the gyro's yaw
// integrates to the heading change with its sign, the rear wheels' distance is the path's within
// the drawn radius error.
TEST(SimCanBus, TheNuScenesReaderReadsItsGyroAndWheels) {
  const std::string dir = freshTempDir("sim_can_bus");
  const sim::SimTrajectory ego = sim::builtinDrive(60.0);
  const std::int64_t stamp0 = 1547120000000000;
  sim::ImuOptions imu = sim::imuPreset(sim::ImuGrade::Navigation);
  imu.rate = 100.0;
  sim::WheelOptions wheels;
  std::vector<CanImuMessage> imu_messages;
  std::vector<CanWheelMessage> wheel_messages;
  sim::simulateCanBus(ego, 0.0, 60.0, 0.0, stamp0, imu, wheels, 4, imu_messages, wheel_messages);
  writeNuScenesCanBus(dir, "sim-0001", imu_messages, wheel_messages);
  const auto signals = readNuScenesCanBus(dir, "sim-0001");
  ASSERT_TRUE(signals.has_value());
  EXPECT_EQ(signals->yaw_rate.size(), 6001u);  // 100 Hz over 60 s
  const auto at = [&](double t) { return stamp0 + std::llround(t * 1e6); };
  EXPECT_NEAR(signals->yaw_rate.integral(at(18), at(29)), normalizeAngle(ego.at(29).z() - ego.at(18).z()), 0.01);
  EXPECT_GT(signals->yaw_rate.integral(at(18), at(29)), 1.0);  // the left turn, counter-clockwise
  const double distance = signals->rear_wheel_rpm.integral(at(1), at(59)) / 60.0 * 2.0 * kPi * wheels.radius;
  const double truth = ego.arcAt(59) - ego.arcAt(1);
  EXPECT_NEAR(distance / truth, 1.0, 4 * wheels.radius_error);
  EXPECT_NE(distance, truth);  // the true radius is not the nominal one
}
