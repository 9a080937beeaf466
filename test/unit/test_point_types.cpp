#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include <pcl/io/pcd_io.h>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/pcd.h"
#include "radar_ndt/point_types.h"

using radar_ndt::PointRadar;

namespace {
pcl::PointCloud<PointRadar> sampleCloud() {
  pcl::PointCloud<PointRadar> c;
  for (int i = 0; i < 50; ++i) {
    PointRadar p(0.5f * i, -1.25f * i, 0.1f, 0.01f * i);
    p.rcs = -5.0f + i;
    p.cov_xx = 0.04f + 0.001f * i;
    p.cov_xy = -0.002f * i;
    p.cov_yy = 0.09f;
    p.doppler = 3.5f - 0.2f * i;
    p.time_offset = -0.05f + 0.001f * i;
    p.sensor_id = static_cast<std::uint16_t>(i % 5);
    c.push_back(p);
  }
  return c;
}

void expectSame(const pcl::PointCloud<PointRadar>& a, const pcl::PointCloud<PointRadar>& b, float tol) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a[i].x, b[i].x, tol);
    EXPECT_NEAR(a[i].y, b[i].y, tol);
    EXPECT_NEAR(a[i].z, b[i].z, tol);
    EXPECT_NEAR(a[i].power, b[i].power, tol);
    EXPECT_NEAR(a[i].rcs, b[i].rcs, tol);
    EXPECT_NEAR(a[i].cov_xx, b[i].cov_xx, tol);
    EXPECT_NEAR(a[i].cov_xy, b[i].cov_xy, tol);
    EXPECT_NEAR(a[i].cov_yy, b[i].cov_yy, tol);
    EXPECT_NEAR(a[i].doppler, b[i].doppler, tol);
    EXPECT_NEAR(a[i].time_offset, b[i].time_offset, tol);
    EXPECT_EQ(a[i].sensor_id, b[i].sensor_id);
  }
}

std::string tmpPath(const std::string& name) {
  return ::testing::TempDir() + "radar_ndt_" + name;
}
}  // namespace

TEST(PointRadar, DefaultsArePowerOneAndNoCovariance) {
  PointRadar p;
  EXPECT_EQ(p.power, 1.0f);
  EXPECT_EQ(p.cov_xx, 0.0f);
  EXPECT_EQ(p.sensor_id, 0);
}

TEST(PointRadar, RoundTripsThroughPclBinaryPcd) {
  const auto cloud = sampleCloud();
  const std::string path = tmpPath("binary.pcd");
  ASSERT_EQ(pcl::io::savePCDFile(path, cloud, true), 0);
  pcl::PointCloud<PointRadar> back;
  ASSERT_EQ(pcl::io::loadPCDFile(path, back), 0);
  expectSame(cloud, back, 0.0f);  // binary is exact
  std::remove(path.c_str());
}

TEST(PointRadar, RoundTripsThroughPclAsciiPcd) {
  const auto cloud = sampleCloud();
  const std::string path = tmpPath("ascii.pcd");
  ASSERT_EQ(pcl::io::savePCDFileASCII(path, cloud), 0);
  pcl::PointCloud<PointRadar> back;
  ASSERT_EQ(pcl::io::loadPCDFile(path, back), 0);
  expectSame(cloud, back, 1e-5f);
  std::ifstream in(path);
  std::string header((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(header.find("FIELDS x y z power rcs cov_xx cov_xy cov_yy doppler time_offset sensor_id"),
            std::string::npos);
  std::remove(path.c_str());
}

TEST(PointRadar, LibraryWrappersRoundTripAndKeepDefaultsForMissingFields) {
  const auto cloud = sampleCloud();
  const std::string path = tmpPath("wrapped.pcd");
  radar_ndt::savePointRadarPcd(path, cloud);
  expectSame(cloud, radar_ndt::loadPointRadarPcd(path), 0.0f);

  pcl::PointCloud<pcl::PointXYZ> xyz;
  xyz.push_back(pcl::PointXYZ(1, 2, 3));
  ASSERT_EQ(pcl::io::savePCDFileBinary(path, xyz), 0);
  const auto loaded = radar_ndt::loadPointRadarPcd(path);
  ASSERT_EQ(loaded.size(), 1u);
  EXPECT_EQ(loaded[0].x, 1.0f);
  EXPECT_EQ(loaded[0].power, 1.0f);  // not in the file: PointRadar's default
  EXPECT_EQ(loaded[0].cov_xx, 0.0f);
  std::remove(path.c_str());
}

TEST(PointRadar, EmptyCloudIsNotAnError) {
  const std::string path = tmpPath("empty.pcd");
  radar_ndt::savePointRadarPcd(path, pcl::PointCloud<PointRadar>());
  EXPECT_TRUE(radar_ndt::loadPointRadarPcd(path).empty());
  std::remove(path.c_str());
}

TEST(PointRadar, UnreadableFileThrowsNamingIt) {
  const std::string path = tmpPath("garbage.pcd");
  {
    std::ofstream out(path);
    out << "this is not a PCD file\n";
  }
  try {
    radar_ndt::loadPointRadarPcd(path);
    FAIL() << "expected IoError";
  } catch (const radar_ndt::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
  std::remove(path.c_str());
}

TEST(PointRadar, HeaderClaimingMorePointsThanTheFileHoldsIsRefusedBeforeAllocating) {
  const std::string path = tmpPath("huge.pcd");
  {
    std::ofstream out(path, std::ios::binary);
    out << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
           "WIDTH 2147483648\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2147483648\nDATA binary\n";
    out << std::string(24, '\0');
  }
  try {
    radar_ndt::loadPointRadarPcd(path);
    FAIL() << "expected IoError";
  } catch (const radar_ndt::IoError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos);
    EXPECT_NE(msg.find("2147483648 points"), std::string::npos) << msg;
  }
  std::remove(path.c_str());
}
