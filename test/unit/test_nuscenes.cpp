// The nuScenes reader: real files from ../shared/data/nuscenes-mini-radar (skipped when absent),
// ascii / binary / binary_compressed equivalence, and malformed copies.
#define PCL_NO_PRECOMPILE
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <pcl/io/pcd_io.h>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/se2.h"

using namespace radar_ndt;
namespace fs = std::filesystem;

namespace {

const std::string kRoot = std::string(RADAR_NDT_SHARED_DATA) + "/nuscenes-mini-radar";

bool haveData() {
  return fs::exists(kRoot + "/v1.0-mini/sensor.json");
}
#define REQUIRE_DATA()                                                                             \
  if (!haveData()) {                                                                               \
    GTEST_SKIP() << "no " << kRoot << " (../shared/data is absent): skipping the real-data check"; \
  }

std::string tmp(const std::string& name) {
  return ::testing::TempDir() + "radar_ndt_nusc_" + name;
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}
void writeAll(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

/// The first sweep file with at least `min_points` points.
std::string someSweep(std::size_t min_points) {
  for (const auto& e : fs::directory_iterator(kRoot + "/sweeps/RADAR_FRONT")) {
    const auto c = readNuScenesRadarPcd(e.path().string(), NuScenesRadarFilter{}, 0);
    if (c.size() >= min_points) return e.path().string();
  }
  return "";
}

void expectIoError(const std::function<void()>& f, const std::string& file, const std::string& fragment) {
  try {
    f();
    ADD_FAILURE() << "no error for " << file << " (expected '" << fragment << "')";
  } catch (const IoError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(fs::path(file).filename().string()), std::string::npos) << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
  }
}

// A small valid radar PCD written by hand: 3 points, fields in a different order from nuScenes.
const char* kAsciiHeader =
    "# .PCD v0.7\nVERSION 0.7\nFIELDS vy vx y x z rcs invalid_state ambig_state x_rms y_rms\n"
    "SIZE 4 4 4 4 4 4 1 1 1 1\nTYPE F F F F F F I I I I\nCOUNT 1 1 1 1 1 1 1 1 1 1\n"
    "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n";

}  // namespace

TEST(NuScenesPcd, Ars408RmsTable) {
  EXPECT_DOUBLE_EQ(ars408RmsValue(0), 0.005);
  EXPECT_DOUBLE_EQ(ars408RmsValue(19), 0.616);
  EXPECT_DOUBLE_EQ(ars408RmsValue(30), 10.0);
  EXPECT_TRUE(std::isnan(ars408RmsValue(31)));
  EXPECT_TRUE(std::isnan(ars408RmsValue(-1)));
}

TEST(NuScenesPcd, AsciiAnyFieldOrderDopplerFiltersAndRms) {
  const std::string path = tmp("order.pcd");
  // (x, y) = (10, 0) receding at 2 m/s; (0, 5) with vy = −1 (approaching); an invalid cluster.
  writeAll(path,
           std::string(kAsciiHeader) + "0 2 0 10 0 5.5 0 3 19 20\n-1 0 5 0 0 -3 0 3 21 21\n0 1 0 20 0 1 1 3 19 19\n");
  NuScenesPcdStats stats;
  const auto c = readNuScenesRadarPcd(path, NuScenesRadarFilter{}, 7, &stats);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(stats.points_in_file, 3u);
  EXPECT_EQ(stats.dropped_by_filter, 1u);  // invalid_state 1
  EXPECT_FLOAT_EQ(c[0].x, 10.f);
  EXPECT_FLOAT_EQ(c[0].doppler, 2.f);
  EXPECT_FLOAT_EQ(c[1].doppler, -1.f);
  EXPECT_FLOAT_EQ(c[0].rcs, 5.5f);
  EXPECT_FLOAT_EQ(c[0].power, 1.f);
  EXPECT_EQ(c[0].sensor_id, 7);
  EXPECT_NEAR(c[0].cov_xx, 0.616 * 0.616, 1e-6);
  EXPECT_NEAR(c[0].cov_yy, 0.794 * 0.794, 1e-6);
  // An empty accept list keeps everything; the range filter applies.
  NuScenesRadarFilter all;
  all.invalid_states.clear();
  all.max_range = 15.0;
  EXPECT_EQ(readNuScenesRadarPcd(path, all, 0).size(), 2u);  // the 20 m point is out of range
}

TEST(NuScenesPcd, NonFinitePointsAreDroppedAndCounted) {
  const std::string path = tmp("nan.pcd");
  writeAll(path, std::string(kAsciiHeader) +
                     "0 2 0 10 0 5.5 0 3 19 20\nnan 0 5 0 0 -3 0 3 21 21\n0 1 inf 20 0 1 0 3 19 19\n");
  NuScenesPcdStats stats;
  const auto c = readNuScenesRadarPcd(path, NuScenesRadarFilter{}, 0, &stats);
  EXPECT_EQ(c.size(), 1u);
  EXPECT_EQ(stats.dropped_non_finite, 2u);
}

TEST(NuScenesPcd, MalformedFilesNameTheFileAndProblem) {
  const std::string good =
      std::string(kAsciiHeader) + "0 2 0 10 0 5.5 0 3 19 20\n-1 0 5 0 0 -3 0 3 21 21\n0 1 0 20 0 1 1 3 19 19\n";
  struct Case {
    const char* name;
    std::string bytes;
    const char* fragment;
  };
  std::string missing_vx = good;
  missing_vx.replace(missing_vx.find(" vx "), 4, " vq ");
  std::string short_line = good.substr(0, good.rfind("0 1 0 20")) + "0 1 0\n";
  const std::vector<Case> cases = {
      {"empty.pcd", "", "empty file"},
      {"text.pcd", "hello world\nthis is not a point cloud\n", "not a PCD file"},
      {"no_data.pcd", std::string(kAsciiHeader).substr(0, std::string(kAsciiHeader).find("DATA")), "no DATA line"},
      {"missing_vx.pcd", missing_vx, "no field 'vx'"},
      {"truncated_ascii.pcd", good.substr(0, good.rfind("0 1 0 20")), "truncated: 2 of 3"},
      {"short_line.pcd", short_line, "3 values, the header declares 10"},
      {"bad_size.pcd", std::string(kAsciiHeader).replace(std::string(kAsciiHeader).find("SIZE 4"), 6, "SIZE 3") + "1\n",
       "size 3"},
      {"bad_count.pcd",
       std::string(kAsciiHeader).replace(std::string(kAsciiHeader).find("POINTS 3"), 8, "POINTS 4") + "1\n",
       "!= POINTS"},
      {"huge.pcd",
       "VERSION 0.7\nFIELDS x y vx vy\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 2147483648\nHEIGHT 1\nPOINTS "
       "2147483648\nDATA binary\n1234",
       "2147483648 points"},
      {"unknown_data.pcd",
       std::string(kAsciiHeader).replace(std::string(kAsciiHeader).find("DATA ascii"), 10, "DATA zip") + "1\n",
       "unknown DATA format"},
  };
  for (const auto& c : cases) {
    const std::string path = tmp(c.name);
    writeAll(path, c.bytes);
    expectIoError([&] { readNuScenesRadarPcd(path, NuScenesRadarFilter{}, 0); }, path, c.fragment);
  }
  expectIoError([&] { readNuScenesRadarPcd(tmp("does_not_exist.pcd"), NuScenesRadarFilter{}, 0); },
                tmp("does_not_exist.pcd"), "no such file");
}

TEST(NuScenesPcd, AmbiguousDopplerKeepsItsPositionWithoutItsDoppler) {
  // Three valid clusters: unambiguous Doppler (3), ambiguous (1), and 2.
  const std::string path = tmp("ambig.pcd");
  writeAll(path,
           std::string(kAsciiHeader) + "0 2 0 10 0 1 0 3 19 19\n0 1 0 20 0 1 0 1 19 19\n0 3 0 30 0 1 0 2 19 19\n");
  NuScenesRadarFilter every;  // the default: every ambig_state kept, every Doppler used
  auto c = readNuScenesRadarPcd(path, every, 0);
  ASSERT_EQ(c.size(), 3u);
  for (const auto& p : c) EXPECT_TRUE(std::isfinite(p.doppler));
  NuScenesRadarFilter devkit;
  devkit.ambig_states = {3};  // the nuScenes devkit's default: the ambiguous ones dropped
  EXPECT_EQ(readNuScenesRadarPcd(path, devkit, 0).size(), 1u);
  NuScenesRadarFilter match_only;
  match_only.doppler_ambig_states = {3};  // kept for the match, their Doppler unused
  c = readNuScenesRadarPcd(path, match_only, 0);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_FLOAT_EQ(c[0].doppler, 2.f);
  EXPECT_TRUE(std::isnan(c[1].doppler));
  EXPECT_TRUE(std::isnan(c[2].doppler));
  EXPECT_FLOAT_EQ(c[2].x, 30.f) << "the position is kept";
}

TEST(NuScenesPcd, RealSweepBinaryMatchesAsciiAndCompressedCopies) {
  REQUIRE_DATA();
  const std::string path = someSweep(20);
  ASSERT_FALSE(path.empty());
  NuScenesRadarFilter all;  // compare every point, whatever its state
  all.invalid_states.clear();
  all.ambig_states.clear();
  all.max_range = 1e9;
  const auto ref = readNuScenesRadarPcd(path, all, 0);
  pcl::PCLPointCloud2 blob;
  ASSERT_EQ(pcl::PCDReader().read(path, blob), 0);
  pcl::PCDWriter writer;
  const std::string ascii = tmp("copy_ascii.pcd"), compressed = tmp("copy_compressed.pcd");
  ASSERT_EQ(writer.writeASCII(ascii, blob, Eigen::Vector4f::Zero(), Eigen::Quaternionf::Identity(), 9), 0);
  ASSERT_EQ(writer.writeBinaryCompressed(compressed, blob), 0);
  for (const std::string& copy : {ascii, compressed}) {
    const auto c = readNuScenesRadarPcd(copy, all, 0);
    ASSERT_EQ(c.size(), ref.size()) << copy;
    for (std::size_t i = 0; i < c.size(); ++i) {
      EXPECT_NEAR(c[i].x, ref[i].x, 1e-4) << copy;
      EXPECT_NEAR(c[i].y, ref[i].y, 1e-4) << copy;
      EXPECT_NEAR(c[i].doppler, ref[i].doppler, 1e-4) << copy;
      EXPECT_NEAR(c[i].cov_xx, ref[i].cov_xx, 1e-5) << copy;
    }
  }
  // Truncated binary data and a corrupted compressed stream.
  const std::string bytes = readAll(path);
  const std::string truncated = tmp("truncated.pcd");
  writeAll(truncated, bytes.substr(0, bytes.size() - 7));
  expectIoError([&] { readNuScenesRadarPcd(truncated, all, 0); }, truncated, "truncated");
  std::string cbytes = readAll(compressed);
  const std::size_t data = cbytes.find("DATA binary_compressed\n") + 23 + 8;  // after the two size words
  for (std::size_t i = data; i < data + 16; ++i)
    cbytes[i] = static_cast<char>(0xff);  // back-references before the start
  const std::string corrupt = tmp("corrupt_compressed.pcd");
  writeAll(corrupt, cbytes);
  expectIoError([&] { readNuScenesRadarPcd(corrupt, all, 0); }, corrupt, "binary_compressed");
}

TEST(NuScenesDataset, RealTablesScenesChannelsCalibrationsPoses) {
  REQUIRE_DATA();
  const NuScenesDataset ds(kRoot);
  ASSERT_EQ(ds.scenes().size(), 5u);
  EXPECT_EQ(ds.radarChannels().size(), 5u);
  const std::set<std::string> channels(ds.radarChannels().begin(), ds.radarChannels().end());
  EXPECT_TRUE(channels.count("RADAR_FRONT"));
  EXPECT_TRUE(channels.count("RADAR_BACK_RIGHT"));
  const auto sweeps = ds.radarSweeps(ds.scene("scene-0061"));
  ASSERT_GT(sweeps.size(), 1000u);
  std::set<std::string> seen;
  for (std::size_t i = 0; i < sweeps.size(); ++i) {
    const auto& s = sweeps[i];
    if (i > 0) {
      EXPECT_LE(sweeps[i - 1].timestamp_us, s.timestamp_us);
    }
    seen.insert(s.channel);
    EXPECT_TRUE(fs::exists(s.path)) << s.path;
    // Calibrations are rigid and the radars sit on the car (within 5 m of the ego origin).
    EXPECT_NEAR(s.sensor_to_ego.linear().determinant(), 1.0, 1e-9);
    EXPECT_LT(s.sensor_to_ego.translation().norm(), 5.0);
    if (i < 200 || i % 50 == 0) {
      EXPECT_NO_THROW(readNuScenesRadarPcd(s.path, NuScenesRadarFilter{}, s.channel_index)) << s.path;
    }
  }
  EXPECT_EQ(seen.size(), 5u);
  // The front radar looks forward, the back-left one backwards-left.
  for (const auto& s : sweeps) {
    const double yaw = std::atan2(s.sensor_to_ego.linear()(1, 0), s.sensor_to_ego.linear()(0, 0));
    if (s.channel == "RADAR_FRONT") {
      EXPECT_NEAR(yaw, 0.0, 0.05);
    } else if (s.channel == "RADAR_BACK_LEFT") {
      EXPECT_NEAR(std::abs(yaw), kPi, 0.2);
    }
  }
  // Ego poses move smoothly: under 1 m between consecutive sweeps of a car at city speed.
  for (std::size_t i = 1; i < sweeps.size(); ++i)
    EXPECT_LT((sweeps[i].ego_to_global.translation() - sweeps[i - 1].ego_to_global.translation()).norm(), 1.0);
  EXPECT_THROW(ds.scene("scene-9999"), std::invalid_argument);
}

TEST(NuScenesDataset, EmptySweepsAreEmptyClouds) {
  REQUIRE_DATA();
  std::size_t empty_files = 0;
  for (const auto& dir : fs::directory_iterator(kRoot + "/sweeps")) {
    for (const auto& e : fs::directory_iterator(dir.path())) {
      std::ifstream in(e.path(), std::ios::binary);
      std::string line;
      bool zero = false;
      for (int i = 0; i < 12 && std::getline(in, line); ++i)
        if (line == "POINTS 0") zero = true;
      if (!zero) continue;
      ++empty_files;
      EXPECT_TRUE(readNuScenesRadarPcd(e.path().string(), NuScenesRadarFilter{}, 0).empty());
      if (empty_files > 20) return;
    }
  }
  if (empty_files == 0) GTEST_SKIP() << "no POINTS 0 sweep in this copy of the data";
}

TEST(NuScenesDataset, MissingAndMalformedTables) {
  REQUIRE_DATA();
  const std::string root = tmp("dataroot");
  fs::remove_all(root);
  fs::create_directories(root + "/v1.0-mini");
  for (const auto& e : fs::directory_iterator(kRoot + "/v1.0-mini"))
    fs::copy_file(e.path(), root + "/v1.0-mini/" + e.path().filename().string());
  ASSERT_NO_THROW(NuScenesDataset ds(root));

  fs::remove(root + "/v1.0-mini/ego_pose.json");
  expectIoError([&] { NuScenesDataset ds(root); }, root + "/v1.0-mini/ego_pose.json", "missing table");
  fs::copy_file(kRoot + "/v1.0-mini/ego_pose.json", root + "/v1.0-mini/ego_pose.json");

  const std::string scene = root + "/v1.0-mini/scene.json";
  writeAll(scene, "[{\"token\": \"x\", \"name\": 5}");
  expectIoError([&] { NuScenesDataset ds(root); }, scene, "invalid JSON");
  writeAll(scene, "[{\"token\": \"x\", \"name\": 5, \"log_token\": \"y\", \"description\": \"\"}]");
  expectIoError([&] { NuScenesDataset ds(root); }, scene, "'name' is not a string");
  writeAll(scene, "[{\"token\": \"x\", \"log_token\": \"y\"}]");
  expectIoError([&] { NuScenesDataset ds(root); }, scene, "missing key 'name'");
  writeAll(scene, "{\"token\": \"x\"}");
  expectIoError([&] { NuScenesDataset ds(root); }, scene, "expected a JSON array");
  EXPECT_THROW(NuScenesDataset ds(tmp("no_such_root")), IoError);
}
