#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/trajectory_io.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;

namespace {
std::string writeText(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "radar_ndt_traj_" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

Trajectory sampleTrajectory(bool stamps) {
  Trajectory t;
  for (int i = 0; i < 20; ++i) {
    Eigen::Isometry3d T = toIsometry3(Pose2(0.5 * i, 0.01 * i * i, 0.05 * i));
    T.translation().z() = 0.001 * i;
    t.poses.push_back(T);
    if (stamps) t.stamps.push_back(1600000000.0 + 0.077 * i);
  }
  return t;
}

void expectSame(const Trajectory& a, const Trajectory& b, double tol) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(a.poses[i].matrix().isApprox(b.poses[i].matrix(), tol)) << i;
  ASSERT_EQ(a.stamps.size(), b.stamps.size());
  for (std::size_t i = 0; i < a.stamps.size(); ++i) EXPECT_NEAR(a.stamps[i], b.stamps[i], 1e-6);
}

/// Expects an IoError whose message contains the file name and `fragment`, and the line number.
void expectError(const std::string& path, const std::string& fragment, std::size_t line, TrajectoryFormat f) {
  try {
    readTrajectory(path, f);
    ADD_FAILURE() << "expected IoError for " << path;
  } catch (const IoError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
    EXPECT_EQ(e.line(), line) << msg;
  }
}
}  // namespace

TEST(TrajectoryIo, KittiRoundTrip) {
  const auto t = sampleTrajectory(false);
  const std::string path = ::testing::TempDir() + "radar_ndt_traj_rt.kitti";
  writeKitti(path, t);
  expectSame(t, readKitti(path), 1e-8);
  expectSame(t, readTrajectory(path), 1e-8);  // auto-detected
}

TEST(TrajectoryIo, TumRoundTrip) {
  const auto t = sampleTrajectory(true);
  const std::string path = ::testing::TempDir() + "radar_ndt_traj_rt.tum";
  writeTum(path, t);
  expectSame(t, readTum(path), 1e-7);
  expectSame(t, readTrajectory(path), 1e-7);
}

TEST(TrajectoryIo, CommentsBlankLinesAndCrlfAreAccepted) {
  const std::string path = writeText(
      "comments.txt", "# t x y z qx qy qz qw\r\n\r\n1.0 1 2 3 0 0 0 1\r\n  \n2.0 1 2 3 0 0 0.7071068 0.7071068\n");
  const auto t = readTum(path);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_NEAR(toPose2(t.poses[1]).z(), kPi / 2, 1e-6);
}

TEST(TrajectoryIo, WriteIsAtomicAndLeavesNoTemporaryFile) {
  const std::string dir = ::testing::TempDir() + "radar_ndt_atomic";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  writeKitti(dir + "/out.txt", sampleTrajectory(false));
  std::size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(e.path().filename(), "out.txt");
  }
  EXPECT_EQ(files, 1u);
  EXPECT_THROW(writeKitti(dir + "/no/such/dir/out.txt", sampleTrajectory(false)), IoError);
  EXPECT_THROW(writeTum(dir + "/x.tum", sampleTrajectory(false)), IoError);  // no stamps
}

struct MalformedCase {
  const char* name;
  const char* text;
  TrajectoryFormat format;
  const char* fragment;
  std::size_t line;
};

class TrajectoryIoMalformed : public ::testing::TestWithParam<MalformedCase> {};

TEST_P(TrajectoryIoMalformed, GivesFileLineAndProblem) {
  const auto& c = GetParam();
  expectError(writeText(c.name, c.text), c.fragment, c.line, c.format);
}

INSTANTIATE_TEST_SUITE_P(
    Table, TrajectoryIoMalformed,
    ::testing::Values(
        MalformedCase{"empty", "", TrajectoryFormat::Auto, "no poses", 0},
        MalformedCase{"only_comments", "# nothing\n\n", TrajectoryFormat::Kitti, "no poses", 0},
        MalformedCase{"kitti_short", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n", TrajectoryFormat::Kitti,
                      "12 numbers, found 11", 2},
        MalformedCase{"kitti_word", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 x 0 1 0 0 0 0 1 0\n", TrajectoryFormat::Kitti,
                      "cannot parse 'x'", 2},
        MalformedCase{"kitti_nan", "1 0 0 nan 0 1 0 0 0 0 1 0\n", TrajectoryFormat::Kitti, "non-finite", 1},
        MalformedCase{"kitti_inf", "1 0 0 0 0 1 0 inf 0 0 1 0\n", TrajectoryFormat::Kitti, "non-finite", 1},
        MalformedCase{"kitti_not_rotation", "2 0 0 0 0 1 0 0 0 0 1 0\n", TrajectoryFormat::Kitti, "not a rotation", 1},
        MalformedCase{"kitti_reflection", "1 0 0 0 0 1 0 0 0 0 -1 0\n", TrajectoryFormat::Kitti, "det", 1},
        MalformedCase{"boreas_not_rotation", "1 0.5 0 0 0 0 1 0 0 0 0 1 0\n", TrajectoryFormat::Boreas,
                      "not a rotation", 1},
        MalformedCase{"kitti_trailing_junk", "1 0 0 0 0 1 0 0 0 0 1 0.5abc\n", TrajectoryFormat::Kitti,
                      "cannot parse '0.5abc'", 1},
        MalformedCase{"auto_bad_columns", "1 2 3 4 5\n", TrajectoryFormat::Auto, "cannot tell the trajectory format",
                      0},
        MalformedCase{"tum_short", "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n", TrajectoryFormat::Tum, "8 numbers", 2},
        MalformedCase{"tum_stamps_backwards", "2.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n", TrajectoryFormat::Tum,
                      "not after the previous", 2},
        MalformedCase{"tum_duplicate_stamp", "1.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n", TrajectoryFormat::Tum,
                      "not after the previous", 2},
        MalformedCase{"tum_zero_quaternion", "1.0 0 0 0 0 0 0 0\n", TrajectoryFormat::Tum, "quaternion norm", 1},
        MalformedCase{"binary", "1 0 0 0 0 1 0 0 0 0 1 0\n\x01\x02\x00\x03 4\n", TrajectoryFormat::Kitti,
                      "cannot parse", 2}),
    [](const ::testing::TestParamInfo<MalformedCase>& i) { return std::string(i.param.name); });

// Files rounded to few decimals (CFEAR's KITTI files keep 3) carry rotation blocks that are not
// orthonormal: read as the nearest rotations and counted, never refused.
TEST(TrajectoryIo, RoundedRotationBlocksAreProjectedAndCounted) {
  const auto t = sampleTrajectory(false);
  std::string text;
  char buf[32];
  for (const auto& T : t.poses)
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) {
        std::snprintf(buf, sizeof(buf), "%.3f", T.matrix()(r, c));
        text += buf;
        text += (r == 2 && c == 3) ? '\n' : ' ';
      }
  const Trajectory read = readTrajectory(writeText("rounded.kitti", text));
  ASSERT_EQ(read.size(), t.size());
  EXPECT_GT(read.projected_rotations, t.size() / 2);
  EXPECT_GT(read.max_rotation_deviation, 1e-4);
  EXPECT_LT(read.max_rotation_deviation, 5e-3);
  for (std::size_t i = 0; i < read.size(); ++i) {
    const Eigen::Matrix3d R = read.poses[i].linear();
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-8) << i;
    EXPECT_NEAR(R.determinant(), 1.0, 1e-8);
    // The nearest rotation: within the rounding of the true one.
    EXPECT_LT(Eigen::AngleAxisd(R.transpose() * t.poses[i].linear()).angle(), 2e-3) << i;
  }
  // An exact file has nothing to project.
  const std::string exact = ::testing::TempDir() + "radar_ndt_traj_exact.kitti";
  writeKitti(exact, t);
  EXPECT_EQ(readKitti(exact).projected_rotations, 0u);
}

// Boreas odometry files are re-orthogonalised as pyboreas utils.enforce_orthog does: columns 1 and 2
// kept in direction, column 0 their cross product (the SDK's scores depend on this choice).
TEST(TrajectoryIo, BoreasBlocksAreOrthogonalisedAsTheSdkDoes) {
  const double c = std::cos(0.3), s = std::sin(0.3);
  char line[256];
  // T_rk_r0 with a yaw of 0.3 in the radar's axes, rounded so that the block is not orthonormal.
  std::snprintf(line, sizeof(line), "1000000 %.3f %.3f 0 1.5 %.3f %.3f 0 -2 0 0 1 0\n", c, -s, s, c);
  const Trajectory t = readTrajectory(writeText("rounded.boreas", line));
  ASSERT_EQ(t.projected_rotations, 1u);
  // The SDK's result, computed here by its steps on the rounded block.
  Eigen::Matrix3d R;
  char num[16];
  auto rounded = [&](double v) {
    std::snprintf(num, sizeof(num), "%.3f", v);
    return std::stod(num);
  };
  R << rounded(c), rounded(-s), 0, rounded(s), rounded(c), 0, 0, 0, 1;
  const Eigen::Vector3d c1 = R.col(1).normalized(), c2 = R.col(2).normalized();
  Eigen::Matrix3d sdk;
  sdk.col(0) = c1.cross(c2);
  sdk.col(1) = c2.cross(Eigen::Vector3d(sdk.col(0)));
  sdk.col(2) = c2;
  // Read back as a vehicle pose: F (T_rk_r0)^-1 F with F = diag(1, -1, -1).
  const Eigen::Matrix3d F = Eigen::Vector3d(1, -1, -1).asDiagonal();
  EXPECT_TRUE(t.poses[0].linear().isApprox(F * sdk.transpose() * F, 1e-15)) << t.poses[0].linear();
}

TEST(TrajectoryIo, MissingFileIsNamed) {
  expectError(::testing::TempDir() + "radar_ndt_no_such_file.txt", "cannot open", 0, TrajectoryFormat::Auto);
}

TEST(TrajectoryIo, ParsesFormatNames) {
  EXPECT_EQ(parseTrajectoryFormat("KITTI"), TrajectoryFormat::Kitti);
  EXPECT_EQ(parseTrajectoryFormat("tum"), TrajectoryFormat::Tum);
  EXPECT_THROW(parseTrajectoryFormat("csv"), std::invalid_argument);
}

// The one lookup of a trajectory at a time: the pose itself at its stamp, the interpolation between
// stamps (the planar interpolation of se2.h, here through 3D slerp), and nothing outside the span
// beyond a microsecond.
TEST(TrajectoryIo, PoseAtInterpolatesBetweenStampsAndRefusesOutsideThem) {
  Trajectory t;
  t.stamps = {10.0, 11.0, 13.0};
  const std::vector<Pose2> planar{Pose2(0, 0, 0.0), Pose2(2.0, 0.0, 0.4), Pose2(2.0, 4.0, -3.0)};
  for (const Pose2& p : planar) t.poses.push_back(toIsometry3(p));
  Eigen::Isometry3d out;
  ASSERT_TRUE(t.poseAt(11.0, &out));
  EXPECT_TRUE(out.isApprox(t.poses[1], 0.0)) << "at a stamp: that pose exactly";
  ASSERT_TRUE(t.poseAt(10.25, &out));
  EXPECT_TRUE(toPose2(out).isApprox(interpolate(planar[0], planar[1], 0.25), 1e-12));
  ASSERT_TRUE(t.poseAt(12.5, &out));  // 0.4 to −3.0 the short way round, through ±π
  EXPECT_TRUE(toPose2(out).isApprox(interpolate(planar[1], planar[2], 0.75), 1e-12)) << toPose2(out).transpose();
  ASSERT_TRUE(t.poseAt(13.0 + 5e-7, &out));
  EXPECT_TRUE(out.isApprox(t.poses[2], 0.0)) << "within a microsecond of the end: the end";
  EXPECT_FALSE(t.poseAt(9.99, &out));
  EXPECT_FALSE(t.poseAt(13.01, &out));
  Trajectory unstamped;
  unstamped.poses = t.poses;
  EXPECT_FALSE(unstamped.poseAt(11.0, &out));
  // In 3D: the rotation by slerp, half way between a roll of 0 and 0.2 rad.
  Trajectory tilted;
  tilted.stamps = {0.0, 2.0};
  tilted.poses = {Eigen::Isometry3d::Identity(), Eigen::Isometry3d(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()))};
  ASSERT_TRUE(tilted.poseAt(1.0, &out));
  EXPECT_NEAR(Eigen::AngleAxisd(out.linear()).angle(), 0.1, 1e-12);
}
