// View-of-Delft's radar layout (radar_ndt/io/view_of_delft.h) on files written in that layout: the
// .bin rows, the pose and calibration chain, the Doppler's sign, and malformed files.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "radar_ndt/frontend/ego_velocity_3d.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/view_of_delft.h"

using namespace radar_ndt;
namespace fs = std::filesystem;

namespace {

/// A fresh VoD root with `frames` frames in radar/training: a car driving forward at `speed` m/s
/// past static points (v_r = −u · v, v_r_compensated 0) and one point moving towards it.
std::string writeLayout(const std::string& name, int frames, double speed) {
  const fs::path root = fs::path(::testing::TempDir()) / ("radar_ndt_vod_" + name);
  fs::remove_all(root);
  for (const char* d : {"velodyne", "calib", "pose"}) fs::create_directories(root / "radar" / "training" / d);
  for (int f = 0; f < frames; ++f) {
    char id[16];  // any int fits (GCC checks the type, not the loop)
    std::snprintf(id, sizeof id, "%05d", 100 + f);
    pcl::PointCloud<PointRadar4D> cloud;
    std::vector<float> compensated;
    for (int i = 0; i < 40; ++i) {
      PointRadar4D p;
      const double az = -0.6 + 0.03 * i, el = 0.1 * std::sin(i), r = 5 + i;
      p.x = static_cast<float>(r * std::cos(el) * std::cos(az));
      p.y = static_cast<float>(r * std::cos(el) * std::sin(az));
      p.z = static_cast<float>(r * std::sin(el));
      p.rcs = static_cast<float>(i % 7) - 10.f;
      const double own = i == 7 ? -4.0 : 0.0;  // one oncoming car
      p.doppler = static_cast<float>(-speed * p.x / r + own);
      p.time_offset = 0.f;
      cloud.push_back(p);
      compensated.push_back(static_cast<float>(own));
    }
    writeVodRadarBin((root / "radar/training/velodyne" / (std::string(id) + ".bin")).string(), cloud, &compensated);
    // The radar 2.5 m ahead of and 0.9 m below the camera, in the camera's axes (x right, y down, z forward).
    std::ofstream(root / "radar/training/calib" / (std::string(id) + ".txt"))
        << "P0: 1 0 0 0 0 1 0 0 0 0 1 0\nP1: 1 0 0 0 0 1 0 0 0 0 1 0\nP2: 1 0 0 0 0 1 0 0 0 0 1 0\n"
        << "P3: 1 0 0 0 0 1 0 0 0 0 1 0\nR0_rect: 1 0 0 0 1 0 0 0 1\n"
        << "Tr_velo_to_cam: 0 -1 0 0.05 0 0 -1 0.9 1 0 0 2.5\nTr_imu_to_velo: \n";
    // The camera at x = 10 + speed · f / 13 along the odom's x, looking forward, 1.3 m up.
    const double x = 10 + speed * f / 13.0;
    std::ofstream(root / "radar/training/pose" / (std::string(id) + ".json"))
        << "{\"odomToCamera\": [0, 0, 1, " << x << ", -1, 0, 0, 0, 0, -1, 0, 1.3, 0, 0, 0, 1]}\n"
        << "{\"mapToCamera\": [0, 0, 1, " << x + 100 << ", -1, 0, 0, 0, 0, -1, 0, 1.3, 0, 0, 0, 1]}\n"
        << "{\"UTMToCamera\": [0, 0, 1, " << x + 593000 << ", -1, 0, 0, 5763000, 0, -1, 0, 1.3, 0, 0, 0, 1]}\n";
  }
  return root.string();
}

template <typename Fn>
std::string ioErrorOf(Fn&& fn) {
  try {
    fn();
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ViewOfDelft, ReadsTheLayoutAsTheDevkitDoes) {
  const std::string root = writeLayout("layout", 3, 2.5);
  const ViewOfDelftSequence seq(root);
  ASSERT_EQ(seq.size(), 3u);
  EXPECT_EQ(seq.id(0), "00100");
  std::vector<float> compensated;
  const auto cloud = seq.load(1, &compensated);
  ASSERT_EQ(cloud.size(), 40u);
  ASSERT_EQ(compensated.size(), 40u);
  EXPECT_FLOAT_EQ(compensated[7], -4.f);
  EXPECT_FLOAT_EQ(cloud[3].rcs, -7.f);
  EXPECT_FLOAT_EQ(cloud[0].power, 1.f);
  // v_r positive receding: the static points' fit is the car driving forward at 2.5 m/s.
  std::vector<bool> inlier;
  const EgoVelocity3D e = EgoVelocity3DEstimator().estimate(cloud, &inlier);
  ASSERT_TRUE(e.valid) << e.why;
  EXPECT_NEAR(e.velocity.x(), 2.5, 1e-3);
  EXPECT_FALSE(inlier[7]);
  // The radar's pose in odom: the camera's pose times T_camera_radar. The radar's axes are the
  // car's (x forward, z up) and it sits 2.5 m ahead of the camera and 0.9 m below it.
  const Eigen::Isometry3d T = seq.radarPose(1);
  EXPECT_TRUE(T.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-9)) << T.linear();
  EXPECT_NEAR(T.translation().x(), 10 + 2.5 / 13.0 + 2.5, 1e-4);  // the JSON holds 6 digits
  EXPECT_NEAR(T.translation().y(), -0.05, 1e-9);
  EXPECT_NEAR(T.translation().z(), 1.3 - 0.9, 1e-9);
  const Trajectory traj = seq.radarTrajectory();
  ASSERT_EQ(traj.size(), 3u);
  EXPECT_FALSE(traj.hasStamps());
  EXPECT_NEAR(readVodCameraPose(seq.posePath(0), "UTMToCamera").translation().y(), 5763000, 1e-6);
}

TEST(ViewOfDelft, MalformedFilesAreErrorsNamingTheFile) {
  const std::string root = writeLayout("bad", 2, 1.0);
  const ViewOfDelftSequence seq(root);
  // A truncated .bin.
  {
    std::ofstream out(seq.binPath(0), std::ios::binary | std::ios::app);
    out << "abc";
  }
  std::string what = ioErrorOf([&] { seq.load(0); });
  EXPECT_NE(what.find(seq.binPath(0)), std::string::npos) << what;
  EXPECT_NE(what.find("truncated"), std::string::npos) << what;
  // A NaN row is left out and counted.
  pcl::PointCloud<PointRadar4D> c = seq.load(1);
  c[5].z = std::numeric_limits<float>::quiet_NaN();
  writeVodRadarBin(seq.binPath(1), c);
  std::size_t dropped = 0;
  EXPECT_EQ(readVodRadarBin(seq.binPath(1), nullptr, &dropped).size(), 39u);
  EXPECT_EQ(dropped, 1u);
  // Pose files: a key missing, a line not JSON, a matrix not rigid.
  std::ofstream(seq.posePath(1)) << "{\"mapToCamera\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}\n";
  what = ioErrorOf([&] { seq.radarPose(1); });
  EXPECT_NE(what.find("odomToCamera"), std::string::npos) << what;
  std::ofstream(seq.posePath(1)) << "{\"odomToCamera\": [1, 0, 0\n";
  what = ioErrorOf([&] { seq.radarPose(1); });
  EXPECT_NE(what.find(seq.posePath(1) + ":1"), std::string::npos) << what;
  std::ofstream(seq.posePath(1)) << "{\"odomToCamera\": [2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}\n";
  EXPECT_NE(ioErrorOf([&] { seq.radarPose(1); }).find("rigid"), std::string::npos);
  std::ofstream(seq.calibPath(0)) << "P0: 1 0 0 0\n";
  EXPECT_NE(ioErrorOf([&] { readVodRadarToCamera(seq.calibPath(0)); }).find("Tr_velo_to_cam"), std::string::npos);
  EXPECT_NE(ioErrorOf([&] { ViewOfDelftSequence(root + "/nowhere"); }).find("velodyne"), std::string::npos);
}
