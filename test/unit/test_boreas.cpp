// Boreas readers: the real 2024 scan (rows, stamps, encoder steps, chirp types, bins), the real
// ground-truth pose file against the SDK's convention on hand-worked rows, the leaderboard's
// odometry format, the time parser and the bin by date, and malformed files.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "radar_ndt/frontend/chirp_correction.h"
#include "radar_ndt/io/boreas_ground_truth.h"
#include "radar_ndt/io/boreas_scan.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/png_image.h"
#include "radar_ndt/io/scanning_sequence.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/pipeline/scanning_run.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/sim/radar_sim.h"
#include "test_support.h"

using namespace radar_ndt;
using radar_ndt::test::freshTempDir;
namespace fs = std::filesystem;

namespace {

const std::string kBoreas = std::string(RADAR_NDT_SHARED_DATA) + "/boreas-sample";
const std::string kScan2024 = kBoreas + "/radar-2024-12-03/radar/1733239501983835.png";
const std::string kPoses2021 = kBoreas + "/boreas-2021-08-05-13-34/applanix/radar_poses.csv";

#define SKIP_WITHOUT(path)                                                                             \
  do {                                                                                                 \
    if (!fs::exists(path)) GTEST_SKIP() << "no " << (path) << " (../shared/data is absent): skipping"; \
  } while (0)

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

template <typename Fn>
std::string errorOf(Fn&& fn) {
  try {
    fn();
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

// Four azimuths a quarter turn apart, 60 bins all at `power`, rows 62.5 ms apart from `stamp0`.
PolarScan smallScan(std::int64_t stamp0, std::uint8_t power) {
  PolarScan s;
  s.azimuths = 4;
  s.bins = 60;
  s.power.assign(static_cast<std::size_t>(s.azimuths) * s.bins, power);
  for (int a = 0; a < s.azimuths; ++a) {
    s.angle.push_back(-2 * kPi * a / 4);
    s.stamp_us.push_back(stamp0 + 62500 * a);
  }
  return s;
}

const char* kHeader =
    "GPSTime,easting,northing,altitude,vel_east,vel_north,vel_up,roll,pitch,heading,angvel_z,angvel_y,angvel_x\n";

}  // namespace

TEST(BoreasTime, ParsesTheWaysTheSdkDoes) {
  double s = 0;
  std::int64_t us = 0;
  ASSERT_TRUE(boreasTimeSeconds("1733239501983835", &s));  // 16 digits: µs
  EXPECT_NEAR(s, 1733239501.983835, 1e-6);
  ASSERT_TRUE(boreasTimeMicros("1733239501983835", &us));
  EXPECT_EQ(us, 1733239501983835);
  ASSERT_TRUE(boreasTimeSeconds("1628184886551599081", &s));  // 19 digits: ns
  EXPECT_NEAR(s, 1628184886.551599, 1e-6);
  ASSERT_TRUE(boreasTimeMicros("1628184886551599081", &us));
  EXPECT_EQ(us, 1628184886551599);                   // rounded down, as a scan is named
  ASSERT_TRUE(boreasTimeMicros("1628184886", &us));  // 10 digits: s
  EXPECT_EQ(us, 1628184886000000);
  ASSERT_TRUE(boreasTimeMicros("16281848865", &us));  // 11 digits: tenths of a second
  EXPECT_EQ(us, 1628184886500000);
  EXPECT_FALSE(boreasTimeMicros("", &us));
  EXPECT_FALSE(boreasTimeMicros("12a4", &us));
  EXPECT_FALSE(boreasTimeSeconds("-1628184886", &s));
}

TEST(BoreasScan, TheBinFollowsTheScanDateAsTheSdk) {
  EXPECT_DOUBLE_EQ(boreasRangeResolution(1628184886.0), 0.0596);   // 2021-08-05
  EXPECT_DOUBLE_EQ(boreasRangeResolution(1733239501.0), 0.04381);  // 2024-12-03
  EXPECT_DOUBLE_EQ(boreasRangeResolution(1632182400.0), 0.0596);   // the upgrade instant: `t > upgrade`
  EXPECT_DOUBLE_EQ(boreasRangeResolution(1632182400.5), 0.04381);
}

TEST(BoreasScan, ReadsTheReal2024Scan) {
  SKIP_WITHOUT(kScan2024);
  const PolarScan s = readBoreasPolarPng(kScan2024);
  ASSERT_EQ(s.azimuths, 400);
  EXPECT_EQ(s.bins, 6848);
  EXPECT_DOUBLE_EQ(s.range_resolution, 0.04381);  // after 2021-09-21
  EXPECT_DOUBLE_EQ(s.range_offset_bins, 0.5);
  EXPECT_EQ(s.stamp, 1733239501983835);  // the file name: row 199's timestamp
  EXPECT_EQ(s.stamp_us[199], s.stamp);
  // Rows 625 µs apart (1/4 s over 400 azimuths), with the jitter of a real sensor's clock.
  int at_625 = 0;
  for (int a = 1; a < s.azimuths; ++a) {
    const std::int64_t d = s.stamp_us[a] - s.stamp_us[a - 1];
    EXPECT_GT(d, 500) << "row " << a;  // real rows jitter (512 to 701 µs in this scan)
    EXPECT_LT(d, 750) << "row " << a;
    at_625 += d == 625;
  }
  EXPECT_GT(at_625, 350);
  EXPECT_EQ(s.stamp_us.back() - s.stamp_us.front(), 249103);
  ASSERT_EQ(s.encoder.size(), 400u);
  for (int a = 0; a < s.azimuths; ++a) {
    EXPECT_EQ(s.encoder[a], 7 + 14 * a) << "row " << a;
    // Clockwise from x forward: the vehicle-frame angle is minus the encoder angle.
    EXPECT_NEAR(std::remainder(s.angle[a] + 2 * kPi * s.encoder[a] / 5600.0, 2 * kPi), 0.0, 1e-12);
  }
  ASSERT_EQ(s.chirp_up.size(), 400u);  // the flag byte alternates: chirp types, not validity
  int up = 0;
  for (int a = 0; a < s.azimuths; ++a) {
    up += s.chirp_up[a];
    if (a > 0) {
      EXPECT_NE(s.chirp_up[a], s.chirp_up[a - 1]);
    }
    EXPECT_EQ(s.measured[a], 1);
  }
  EXPECT_EQ(up, 200);
  // The SDK zeroes the bins under 2.5 m: round(2.5 / 0.04381) = 57 of them.
  int nonzero_before = 0, nonzero_after = 0;
  for (int a = 0; a < s.azimuths; ++a) {
    for (int b = 0; b < 57; ++b) nonzero_before += s.row(a)[b] != 0;
    nonzero_after += s.row(a)[57] != 0;
  }
  EXPECT_EQ(nonzero_before, 0);
  EXPECT_GT(nonzero_after, 0);
  // Read as validity flags on request, half the azimuths are "interpolated".
  BoreasPolarOptions validity;
  validity.flag = BoreasFlag::Validity;
  const PolarScan v = readBoreasPolarPng(kScan2024, validity);
  EXPECT_TRUE(v.chirp_up.empty());
  int measured = 0;
  for (auto m : v.measured) measured += m;
  EXPECT_EQ(measured, 200);
}

TEST(BoreasScan, WriterAndReaderAgree) {
  const std::string dir = freshTempDir("boreas_scan_roundtrip");
  PolarScan s = smallScan(1628184886000000, 200);
  s.range_resolution = 0.0596;
  s.range_offset_bins = 0.5;
  s.chirp_up = {0, 1, 0, 1};
  const std::string path = dir + "/1628184886062500.png";  // row 1 = floor(4 / 2) − 1
  writeBoreasPolarPng(path, s);
  const PolarScan r = readBoreasPolarPng(path);
  EXPECT_EQ(r.stamp, 1628184886062500);
  EXPECT_DOUBLE_EQ(r.range_resolution, 0.0596);
  EXPECT_EQ(r.chirp_up, s.chirp_up);
  EXPECT_EQ(r.encoder, (std::vector<std::uint16_t>{0, 1400, 2800, 4200}));
  for (int b = 0; b < 42; ++b) EXPECT_EQ(r.row(0)[b], 0) << b;  // round(2.5 / 0.0596) = 42 zeroed
  EXPECT_EQ(r.row(0)[42], 200);
}

TEST(BoreasGroundTruth, ReadsTheRealPoseFile) {
  SKIP_WITHOUT(kPoses2021);
  const std::vector<BoreasPose> rows = readBoreasPoses(kPoses2021);
  ASSERT_EQ(rows.size(), 4477u);
  EXPECT_EQ(rows[0].time_digits, 19);  // nanoseconds, although the reference says µs
  EXPECT_EQ(rows[0].stamp_us, 1628184886551599);
  EXPECT_NEAR(rows[0].roll, 3.131351979919707, 1e-15);  // the radar's z points down
  EXPECT_NEAR(rows[1600].heading, -2.750729814411979, 1e-15);
}

// Radar-frame motions computed by hand with the SDK's formulas (get_transform with roll and pitch
// rounded to multiples of π, then inv(T_i) · T_j): x forward, y right, yaw clockwise.
TEST(BoreasGroundTruth, MotionsFollowTheSdkConvention) {
  SKIP_WITHOUT(kPoses2021);
  const std::vector<BoreasPose> rows = readBoreasPoses(kPoses2021);
  const Trajectory t = boreasRadarTrajectory(rows);
  ASSERT_EQ(t.size(), rows.size());
  EXPECT_DOUBLE_EQ(t.stamps[0], 1628184886.551599);
  struct Case {
    std::size_t i, j;
    double x, y, yaw;  // the SDK's radar-frame motion
  };
  for (const Case& c :
       {Case{1600, 1601, 3.510293118, -0.007645408, 0.000501805},
        Case{2200, 2204, 15.942833289, 0.249420972, 0.036319643}, Case{0, 1, -0.000016239, 0.000025588, 0.000021173}}) {
    const Pose2 d = between(toPose2(t.poses[c.i]), toPose2(t.poses[c.j]));  // vehicle frame, z up
    EXPECT_NEAR(d.x(), c.x, 1e-8) << c.i << "->" << c.j;
    EXPECT_NEAR(-d.y(), c.y, 1e-8) << c.i << "->" << c.j;
    EXPECT_NEAR(-d.z(), c.yaw, 1e-8) << c.i << "->" << c.j;
  }
  // Through the generic reader too: a pose CSV is recognised by its header.
  const Trajectory auto_read = readTrajectory(kPoses2021);
  ASSERT_EQ(auto_read.size(), t.size());
  EXPECT_TRUE(auto_read.poses[2200].isApprox(t.poses[2200]));
}

// The 6-DoF trajectory: the planar one's x, y and heading, with the altitude and the car's own
// roll and pitch (a few degrees) kept; z up.
TEST(BoreasGroundTruth, TheSixDofTrajectoryKeepsHeightRollAndPitch) {
  SKIP_WITHOUT(kPoses2021);
  const std::vector<BoreasPose> rows = readBoreasPoses(kPoses2021);
  const Trajectory planar = boreasRadarTrajectory(rows), full = boreasRadarTrajectory6Dof(rows);
  ASSERT_EQ(full.size(), rows.size());
  double max_tilt = 0;
  for (std::size_t k = 0; k < full.size(); k += 97) {
    const Eigen::Isometry3d& T = full.poses[k];
    EXPECT_NEAR(T.translation().x(), planar.poses[k].translation().x(), 1e-6);
    EXPECT_NEAR(T.translation().y(), planar.poses[k].translation().y(), 1e-6);
    EXPECT_NEAR(T.translation().z(), rows[k].position.z(), 1e-9);
    // The heading: the body's x projected on the ground.
    const Eigen::Vector3d x = T.linear().col(0);
    EXPECT_NEAR(std::remainder(std::atan2(x.y(), x.x()) - toPose2(planar.poses[k]).z(), 2 * kPi), 0.0, 0.01)
        << k;                                                          // the planar heading drops roll and pitch first
    const double tilt = std::acos(T.linear().col(2).z()) * 180 / kPi;  // the body's z from up
    max_tilt = std::max(max_tilt, tilt);
    EXPECT_NEAR(tilt, std::hypot(rows[k].pitch, kPi - std::abs(rows[k].roll)) * 180 / kPi, 0.05) << k;
  }
  EXPECT_GT(max_tilt, 0.5);  // a real drive tilts
  EXPECT_LT(max_tilt, 10.0);
}

TEST(BoreasGroundTruth, PlanarPosesRoundTrip) {
  const std::string dir = freshTempDir("boreas_poses_roundtrip");
  std::vector<BoreasPose> rows;
  for (int k = 0; k < 5; ++k)
    rows.push_back(boreasPoseFromPlanar(1628185286.5 + 0.25 * k, 100.0 + 3 * k, -20.0 + k, 2.9 + 0.1 * k, 12, 0, 0.4));
  writeBoreasPoses(dir + "/radar_poses.csv", rows);
  const std::vector<BoreasPose> back = readBoreasPoses(dir + "/radar_poses.csv");
  ASSERT_EQ(back.size(), rows.size());
  EXPECT_EQ(back[0].time_digits, 19);
  const Trajectory t = boreasRadarTrajectory(back);
  for (int k = 0; k < 5; ++k) {
    const Pose2 p = toPose2(t.poses[k]);
    EXPECT_NEAR(p.x(), 100.0 + 3 * k, 1e-9);
    EXPECT_NEAR(p.y(), -20.0 + k, 1e-9);
    EXPECT_NEAR(std::remainder(p.z() - (2.9 + 0.1 * k), 2 * kPi), 0.0, 1e-12);
    EXPECT_EQ(back[k].stamp_us, rows[k].stamp_us);
  }
  EXPECT_NEAR(back[0].angular_velocity.z(), -0.4, 1e-15);  // about the radar's downward z
}

TEST(BoreasOdometryFormat, WritesTheLeaderboardsRadarFrameAndReadsItBack) {
  const std::string dir = freshTempDir("boreas_odometry_format");
  Trajectory t;
  t.stamps = {1628185286.559054, 1628185286.808977};
  t.poses = {toIsometry3(Pose2(0, 0, 0)), toIsometry3(Pose2(3.5, 0.5, 0.1))};  // forward, left, CCW
  writeTrajectory(dir + "/seq.txt", t, TrajectoryFormat::Boreas);
  std::ifstream in(dir + "/seq.txt");
  std::string first, second;
  std::getline(in, first);
  std::getline(in, second);
  EXPECT_EQ(first, "1628185286559054 1 0 0 0 0 1 0 0 0 0 1 0");
  // T_r1_r0 in the radar's axes: the inverse motion with y and the yaw's sine negated.
  const Pose2 inv = inverse(Pose2(3.5, 0.5, 0.1));
  std::istringstream ss(second);
  double v[13];
  for (double& x : v) ss >> x;
  EXPECT_EQ(static_cast<std::int64_t>(v[0]), 1628185286808977);
  EXPECT_NEAR(v[1], std::cos(0.1), 1e-11);
  // The vehicle turned 0.1 rad counter-clockwise seen from above: about the radar's downward z
  // that is −0.1, and T_r1_r0 is its inverse, Rz(+0.1) = [[c, −s], [s, c]].
  EXPECT_NEAR(v[2], -std::sin(0.1), 1e-11);
  EXPECT_NEAR(v[5], std::sin(0.1), 1e-11);
  EXPECT_NEAR(v[4], inv.x(), 1e-10);
  EXPECT_NEAR(v[8], -inv.y(), 1e-10);
  EXPECT_NEAR(v[11], 1.0, 1e-12);                            // z down stays z down
  const Trajectory back = readTrajectory(dir + "/seq.txt");  // 13 columns: Boreas
  ASSERT_EQ(back.size(), 2u);
  EXPECT_NEAR(back.stamps[1], t.stamps[1], 1e-6);
  EXPECT_TRUE(back.poses[1].isApprox(t.poses[1], 1e-9));
}

TEST(BoreasBadInput, PoseFilesFailNamingFileAndLine) {
  const std::string dir = freshTempDir("boreas_bad_poses");
  const std::string row = "1628184886551599081,1,2,3,0,0,0,3.14,0,0.2,0,0,0\n";
  const std::string later = "1628184886801550666,1,2,3,0,0,0,3.14,0,0.2,0,0,0\n";
  struct Case {
    std::string text, expect;
  };
  for (const Case& c :
       {Case{"", "empty file"}, Case{"time,x,y\n" + row, "header has 3 columns"},
        Case{std::string(kHeader).replace(0, 7, "GPSTIME") + row, "header column 1 is 'GPSTIME'"},
        Case{std::string(kHeader) + "1628184886551599081,1,2\n", ":2: expected 13 columns, found 3"},
        Case{std::string(kHeader) + "16281848a6551599081,1,2,3,0,0,0,3.14,0,0.2,0,0,0\n", "is not a time"},
        Case{std::string(kHeader) + "1628184886551599081,1,nan,3,0,0,0,3.14,0,0.2,0,0,0\n", "northing"},
        Case{std::string(kHeader) + later + row, ":3: GPSTime"}, Case{std::string(kHeader), "no pose rows"}}) {
    writeText(dir + "/radar_poses.csv", c.text);
    const std::string e = errorOf([&] { readBoreasPoses(dir + "/radar_poses.csv"); });
    EXPECT_NE(e.find(dir + "/radar_poses.csv"), std::string::npos) << e;
    EXPECT_NE(e.find(c.expect), std::string::npos) << "expected '" << c.expect << "' in: " << e;
  }
}

TEST(BoreasBadInput, SequencesAndScansFailClearly) {
  const std::string dir = freshTempDir("boreas_bad_sequence");
  std::string e = errorOf([&] { ScanningSequence(dir, ScanFormat::Boreas); });
  EXPECT_NE(e.find(dir + "/radar"), std::string::npos) << e;
  EXPECT_NE(e.find("missing"), std::string::npos) << e;
  fs::create_directories(dir + "/radar");
  writeText(dir + "/radar/notes.png", "x");
  e = errorOf([&] { ScanningSequence(dir, ScanFormat::Boreas); });
  EXPECT_NE(e.find("lists no scans"), std::string::npos) << e;
  // A truncated scan and one too narrow for the metadata.
  writeText(dir + "/radar/1628184886551599.png", "\x89PNG\r\n\x1a\n");
  e = errorOf([&] { readBoreasPolarPng(dir + "/radar/1628184886551599.png"); });
  EXPECT_NE(e.find(dir + "/radar/1628184886551599.png"), std::string::npos) << e;
  const std::uint8_t narrow[10] = {};
  writePng(dir + "/radar/1628184886801550.png", 10, 1, 1, narrow);
  e = errorOf([&] { readBoreasPolarPng(dir + "/radar/1628184886801550.png"); });
  EXPECT_NE(e.find("11 metadata bytes"), std::string::npos) << e;
  const ScanningSequence s(dir, ScanFormat::Boreas);
  EXPECT_EQ(s.size(), 2u);
  ASSERT_EQ(s.indexProblems().size(), 1u);
  EXPECT_NE(s.indexProblems()[0].find("notes.png"), std::string::npos);
  EXPECT_FALSE(s.hasGroundTruth());
}

TEST(BoreasDefaults, ChirpScansGetTheirOwnThresholdOthersThePapers) {
  const std::string dir = freshTempDir("boreas_defaults");
  PolarScan s = smallScan(1733239501983835, 10);
  fs::create_directories(dir + "/plain/radar");
  writeBoreasPolarPng(dir + "/plain/radar/1733239502046335.png", s);
  s.chirp_up = {0, 1, 0, 1};
  fs::create_directories(dir + "/chirps/radar");
  writeBoreasPolarPng(dir + "/chirps/radar/1733239502046335.png", s);
  const ScanningRunOptions paper;
  const ScanningRunOptions plain = defaultScanningOptions(ScanningSequence(dir + "/plain", ScanFormat::Boreas));
  EXPECT_EQ(plain.front_end.threshold, paper.front_end.threshold);
  EXPECT_EQ(plain.matcher.power_shift, paper.matcher.power_shift);
  const ScanningRunOptions chirps = defaultScanningOptions(ScanningSequence(dir + "/chirps", ScanFormat::Boreas));
  EXPECT_EQ(chirps.front_end.threshold, kBoreasChirpThreshold);
  EXPECT_EQ(chirps.matcher.power_shift, kBoreasChirpThreshold);
  EXPECT_GT(kBoreasChirpThreshold, paper.front_end.threshold);
}

// The simulator's Boreas layout: each scan named by its row 199 (the sweep's middle), and the pose
// file's row for it the vehicle's pose at that instant, in the dataset's units.
TEST(BoreasSimLayout, ScansAreNamedByTheirMiddleRowAndPosedThere) {
  const std::string dir = freshTempDir("boreas_sim_layout");
  const sim::SimTrajectory ego = sim::builtinDrive(20.0);
  sim::WorldOptions world;
  sim::ScanningOptions scanning;
  sim::applyProfile(sim::ScanningProfile::Oxford, world, scanning);
  scanning.bins = 800;  // small scans: only the layout is checked here
  scanning.range_resolution = kBoreasBinBeforeUpgrade;
  sim::SequenceOptions seq;
  seq.start = 20;
  seq.frames = 3;
  seq.start_stamp_us = 1628185286000000;
  sim::BoreasLayoutOptions layout;
  layout.enu_east = 1000.0;
  layout.enu_north = 2000.0;
  sim::writeBoreasSequence(dir, ego, world, scanning, seq, layout);
  const ScanningSequence s(dir, ScanFormat::Boreas);
  ASSERT_EQ(s.size(), 3u);
  ASSERT_TRUE(s.hasGroundTruth());
  const std::vector<BoreasPose> rows = readBoreasPoses(dir + "/applanix/radar_poses.csv");
  ASSERT_EQ(rows.size(), 3u);
  const double t0 = ego.stamps()[seq.start];
  for (std::size_t k = 0; k < 3; ++k) {
    const PolarScan scan = s.load(k);
    EXPECT_EQ(scan.stamp, scan.stamp_us[199]);
    EXPECT_EQ(rows[k].stamp_us, scan.stamp);
    EXPECT_EQ(rows[k].time_digits, 19);
    EXPECT_TRUE(scan.chirp_up.empty());
    // The scan's middle row is at trajectory pose start + k.
    const double t = t0 + 1e-6 * static_cast<double>(scan.stamp - seq.start_stamp_us);
    EXPECT_NEAR(t, ego.stamps()[seq.start + k], 1e-6);
    const Pose2 truth = ego.at(t);
    EXPECT_NEAR(rows[k].position.x(), truth.x() + 1000.0, 1e-6);
    EXPECT_NEAR(rows[k].position.y(), truth.y() + 2000.0, 1e-6);
    EXPECT_NEAR(std::remainder(rows[k].heading - truth.z(), 2 * kPi), 0.0, 1e-9);
  }
}

// The simulator's chirp model: driving forward at 10 m/s, the scenery straight ahead approaches
// (v_r = −10 m/s), so an up-chirp azimuth shows it β·10 m nearer and a down-chirp one as much
// farther; straight abeam (v_r = 0) nothing moves.
TEST(BoreasSimLayout, ChirpsShiftRangesByTheRadialVelocityInOppositeDirections) {
  const sim::SimTrajectory ego({0.0, 1.0, 2.0}, {Pose2(0, 0, 0), Pose2(10, 0, 0), Pose2(20, 0, 0)});
  PolarScan s;
  s.azimuths = 4;
  s.bins = 400;
  s.range_resolution = 0.0596;
  s.power.assign(static_cast<std::size_t>(s.azimuths) * s.bins, 0);
  for (int a = 0; a < s.azimuths; ++a) {
    s.angle.push_back(a < 2 ? 0.0 : kPi / 2);  // rows 0, 1 straight ahead; 2, 3 to the left
    s.stamp_us.push_back(1000000);
    s.row(a)[200] = 250;
  }
  s.chirp_up = {1, 0, 1, 0};
  const double beta = 0.049;
  sim::applyChirpShift(s, ego, 0.0, 0, beta);
  auto peak = [&](int a) { return static_cast<int>(std::max_element(s.row(a), s.row(a) + s.bins) - s.row(a)); };
  const double bins = beta * 10.0 / 0.0596;                      // 8.2
  EXPECT_EQ(peak(0), static_cast<int>(std::round(200 - bins)));  // up-chirp: nearer
  EXPECT_EQ(peak(1), static_cast<int>(std::round(200 + bins)));  // down-chirp: farther
  EXPECT_EQ(peak(2), 200);
  EXPECT_EQ(peak(3), 200);
  EXPECT_EQ(s.row(2)[200], 250);
}

// The chirp correction on the real 2024 scan: a clear fit over most neighbouring pairs, and no
// motion, as the car stood (a moving car at 10 m/s would show |u| = β·v of about 0.5 m).
TEST(BoreasScan, TheRealChirpScanFitsAStandingRadar) {
  SKIP_WITHOUT(kScan2024);
  const ChirpShiftEstimate e = estimateChirpShift(readBoreasPolarPng(kScan2024));
  ASSERT_TRUE(e.valid);
  EXPECT_GT(e.pairs, 250);
  EXPECT_LT(e.u.norm(), 0.03) << e.u.transpose();
  EXPECT_LT(e.rms, 0.1);
}
