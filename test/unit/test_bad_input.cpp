// The bad-input suite: for every reader, a table of malformed files, each of which must give an
// IoError whose message names the file and the problem (never a crash, a huge allocation or a
// silently wrong result), plus the inputs the fuzzers (test/fuzz/) found, as regression tests. More
// cases per reader live beside each reader's own tests (test_trajectory_io, test_nuscenes,
// test_polar_scan); this file holds the ones a single table covers across readers.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <vector>

#include <gtest/gtest.h>
#include <zlib.h>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/nuscenes.h"
#include "radar_ndt/io/nuscenes_writer.h"
#include "radar_ndt/io/oxford_ground_truth.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/pcd.h"
#include "radar_ndt/io/png_image.h"
#include "radar_ndt/io/radiate_scan.h"
#include "radar_ndt/io/scanning_sequence.h"
#include "radar_ndt/io/trajectory_io.h"
#include "test_support.h"

using namespace radar_ndt;

namespace {

void writeAll(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

/// A small valid 8-bit grayscale PNG (width × height), as bytes.
std::string smallPng(const std::string& dir, int width, int height) {
  std::vector<std::uint8_t> px(static_cast<std::size_t>(width) * height, 7);
  const std::string path = dir + "/small.png";
  writePng(path, width, height, 1, px.data());
  return test::readBytes(path);
}

/// `png` with its IHDR declaring width × height (CRC recomputed, so libpng accepts the header).
std::string withDeclaredSize(std::string png, std::uint32_t width, std::uint32_t height) {
  const std::size_t ihdr = 8 + 4;  // signature, chunk length; then "IHDR" and 13 data bytes
  for (int i = 0; i < 4; ++i) {
    png[ihdr + 4 + i] = static_cast<char>((width >> (24 - 8 * i)) & 0xff);
    png[ihdr + 8 + i] = static_cast<char>((height >> (24 - 8 * i)) & 0xff);
  }
  const uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(png.data() + ihdr), 4 + 13);
  for (int i = 0; i < 4; ++i) png[ihdr + 17 + i] = static_cast<char>((crc >> (24 - 8 * i)) & 0xff);
  return png;
}

struct BadFile {
  const char* reader;
  const char* name;
  std::string bytes;
  const char* fragment;  ///< what the message must say
};

using Reader = std::function<void(const std::string&)>;

Reader readerFor(const std::string& name) {
  if (name == "oxford_png") return [](const std::string& p) { readOxfordPolarPng(p); };
  if (name == "radiate_png") return [](const std::string& p) { readRadiatePolarPng(p, 0); };
  if (name == "radar.timestamps") return [](const std::string& p) { readOxfordTimestamps(p); };
  if (name == "Navtech_Polar.txt") return [](const std::string& p) { readRadiateFrameTimes(p); };
  if (name == "radar_odometry.csv") return [](const std::string& p) { readOxfordRadarOdometry(p); };
  if (name == "nuscenes_pcd") return [](const std::string& p) { readNuScenesRadarPcd(p, NuScenesRadarFilter{}, 0); };
  if (name == "point_radar_pcd") return [](const std::string& p) { loadPointRadarPcd(p); };
  if (name == "trajectory") return [](const std::string& p) { readTrajectory(p); };
  throw std::invalid_argument(name);
}

const char* kPcdHeader =
    "VERSION 0.7\nFIELDS x y z power\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 3\nHEIGHT 1\n"
    "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n";

}  // namespace

TEST(BadInput, EveryReaderNamesTheFileAndTheProblem) {
  const std::string dir = test::freshTempDir("bad_input");
  const std::string png = smallPng(dir, 40, 16);
  const std::string csv_header =
      "source_timestamp,destination_timestamp,x,y,z,roll,pitch,yaw,source_radar_timestamp,destination_radar_"
      "timestamp\n";
  const std::vector<BadFile> cases = {
      // Polar PNGs: not PNG, truncated, a header declaring more pixels than the file can hold
      // (refused before the image is allocated), absurd sizes.
      {"oxford_png", "text.png", "timestamp,x\n1,2\n", "not a PNG"},
      {"oxford_png", "truncated.png", png.substr(0, png.size() - 20), "PNG"},
      {"oxford_png", "declares_more.png", withDeclaredSize(png, 3779, 60000), "more than its"},
      {"oxford_png", "absurd.png", withDeclaredSize(png, 1u << 20, 1u << 20), "IHDR"},  // libpng's own limit
      {"radiate_png", "empty.png", "", "empty file"},
      {"radiate_png", "jpeg.png", "\xff\xd8\xff\xe0\x00\x10JFIF\x00", "not a PNG"},
      {"radiate_png", "declares_more.png", withDeclaredSize(png, 400, 200000), "more than its"},
      {"radiate_png", "header_only.png", png.substr(0, 33), "PNG"},
      // Sequence indexes.
      {"radar.timestamps", "dup.timestamps", "1547120000000000 1\n1547120000000000 1\n", "duplicated timestamp"},
      {"radar.timestamps", "words.timestamps", "1547120000000000 1\nnot a number\n", ":2"},
      {"radar.timestamps", "huge.timestamps", "99999999999999999999999 1\n", "cannot parse timestamp"},
      {"Navtech_Polar.txt", "dup.txt",
       "Frame: 000001 Time: 1574859771.744660272\nFrame: 000002 Time: 1574859771.744660272\n", "duplicated frame time"},
      {"Navtech_Polar.txt", "backwards.txt", "Frame: 000001 Time: 1574859771.9\nFrame: 000002 Time: 1574859771.5\n",
       "out of order"},
      {"Navtech_Polar.txt", "overflow.txt", "Frame: 000001 Time: 157485977192577.5\n",
       "out of range"},  // fuzz: UB before
      {"Navtech_Polar.txt", "frame.txt", "Frame: 12345678 Time: 1574859771.5\n", "outside 0..999999"},
      {"Navtech_Polar.txt", "layout.txt", "1574859771.5\n", "expected 'Frame:"},
      {"radar_odometry.csv", "nan.csv", csv_header + "2,1,nan,0,0,0,0,0.01,2,1\n", "not finite"},
      {"radar_odometry.csv", "empty.csv", "", "header"},
      // PCD: empty, not PCD, missing fields, absurd point counts (checked against the file size
      // before anything is allocated), truncated binary data, a wrong value count in ascii.
      {"nuscenes_pcd", "empty.pcd", "", "empty file"},
      {"nuscenes_pcd", "no_vx.pcd", std::string(kPcdHeader) + "1 2 3 1\n1 2 3 1\n1 2 3 1\n", "no field 'vx'"},
      {"point_radar_pcd", "empty.pcd", "", "empty file"},
      {"point_radar_pcd", "text.pcd", "hello\n", "not a PCD file"},
      {"point_radar_pcd", "no_y.pcd",
       "VERSION 0.7\nFIELDS x z\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2\n",
       "no field 'y'"},
      {"point_radar_pcd", "huge.pcd",
       "VERSION 0.7\nFIELDS x y\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\nWIDTH 2147483648\nHEIGHT 1\nPOINTS 2147483648\nDATA "
       "binary\n12345678",
       "2147483648 points"},
      {"point_radar_pcd", "truncated.pcd",
       "VERSION 0.7\nFIELDS x y\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\nWIDTH 4\nHEIGHT 1\nPOINTS 4\nDATA binary\n12345678",
       "truncated"},
      {"point_radar_pcd", "short_line.pcd", std::string(kPcdHeader) + "1 2 3 1\n1 2 3\n1 2 3 1\n",
       "3 values, the header declares 4"},
      // Trajectories.
      {"trajectory", "nan.txt", "1 0 0 nan 0 1 0 0 0 0 1 0\n", "non-finite"},
      {"trajectory", "binary.txt", std::string("\x00\x01\x02\x03", 4), "binary data"},
  };
  for (const BadFile& c : cases) {
    const std::string path = dir + "/" + c.name;
    writeAll(path, c.bytes);
    try {
      readerFor(c.reader)(path);
      ADD_FAILURE() << c.reader << " accepted " << c.name;
    } catch (const IoError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path), std::string::npos) << c.reader << ": " << what;
      EXPECT_NE(what.find(c.fragment), std::string::npos)
          << c.reader << " on " << c.name << ": '" << what << "' lacks '" << c.fragment << "'";
    } catch (const std::exception& e) {
      ADD_FAILURE() << c.reader << " on " << c.name << " threw a non-IoError: " << e.what();
    }
  }
}

TEST(BadInput, LenientIndexReadersSkipAndReportBadLines) {
  const std::string dir = test::freshTempDir("bad_index");
  const std::string ts = dir + "/radar.timestamps";
  writeAll(ts, "100 1\n200 1\n200 1\ngarbage\n150 1\n300 1\n");
  std::vector<IoError> skipped;
  const auto stamps = readOxfordTimestamps(ts, &skipped);
  ASSERT_EQ(stamps.size(), 3u);
  EXPECT_EQ(stamps[2].stamp, 300);
  ASSERT_EQ(skipped.size(), 3u);
  EXPECT_EQ(skipped[0].line(), 3u);
  EXPECT_EQ(skipped[1].line(), 4u);
  EXPECT_EQ(skipped[2].line(), 5u);
  const std::string nav = dir + "/Navtech_Polar.txt";
  writeAll(nav, "Frame: 000001 Time: 10.5\nFrame: 000002 Time: 10.5\nFrame: 000003 Time: 10.75\n");
  skipped.clear();
  const auto frames = readRadiateFrameTimes(nav, &skipped);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1].frame, 3);
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_EQ(skipped[0].file(), nav);
}

TEST(BadInput, PointFilesDropAndCountNonFinitePointsAndReadEmptyScans) {
  const std::string dir = test::freshTempDir("bad_points");
  const std::string path = dir + "/nan.pcd";
  writeAll(path, std::string(kPcdHeader) + "1 2 0 0.5\nnan 2 0 1\n1e39 2 0 1\n");
  std::size_t dropped = 0;
  const auto cloud = loadPointRadarPcd(path, &dropped);
  ASSERT_EQ(cloud.size(), 1u);
  EXPECT_EQ(dropped, 2u) << "NaN, and a value beyond float's range";
  EXPECT_FLOAT_EQ(cloud[0].power, 0.5f);
  const std::string empty = dir + "/empty_scan.pcd";
  writeAll(
      empty,
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 0\nHEIGHT 1\nPOINTS 0\nDATA binary\n");
  EXPECT_TRUE(loadPointRadarPcd(empty).empty());
  // The PointRadar round trip still holds with our reader (binary and ascii).
  pcl::PointCloud<PointRadar> c;
  PointRadar p(1.5f, -2.f, 0.25f, 0.75f);
  p.doppler = -3.f;
  p.sensor_id = 4;
  p.cov_xy = 0.01f;
  c.push_back(p);
  for (bool binary : {true, false}) {
    const std::string out = dir + (binary ? "/rt_bin.pcd" : "/rt_ascii.pcd");
    savePointRadarPcd(out, c, binary);
    const auto back = loadPointRadarPcd(out);
    ASSERT_EQ(back.size(), 1u);
    EXPECT_FLOAT_EQ(back[0].x, 1.5f);
    EXPECT_FLOAT_EQ(back[0].power, 0.75f);
    EXPECT_FLOAT_EQ(back[0].doppler, -3.f);
    EXPECT_FLOAT_EQ(back[0].cov_xy, 0.01f);
    EXPECT_EQ(back[0].sensor_id, 4);
  }
}

TEST(BadInput, FuzzerFindingsStayFixed) {
  // Inputs the fuzzers found (test/fuzz/run.sh), kept in test/data/fuzz_regressions: each gives
  // the result the file holds, read independently here, under every reader that takes its kind.
  const std::string dir = std::string(RADAR_NDT_TEST_DATA) + "/fuzz_regressions";
  // pcl::PCDReader read freed memory on this header (heap-use-after-free under ASan). It is a
  // binary PCD of 5 points of 43 bytes in the nuScenes field layout, one field name garbled
  // ("invalid_staepth"): x, y, z are its first three floats.
  const std::string pcd = dir + "/pcl_reader_use_after_free.pcd";
  const std::string bytes = test::readBytes(pcd);
  const std::size_t data = bytes.find("DATA binary\n") + 12;
  ASSERT_NE(data, std::string::npos + 12);
  std::vector<float> xs, ys;
  for (std::size_t i = 0; i < 5; ++i) {
    float xy[2];
    std::memcpy(xy, bytes.data() + data + 43 * i, sizeof xy);
    xs.push_back(xy[0]);
    ys.push_back(xy[1]);
  }
  std::size_t dropped = 0;
  const auto cloud = loadPointRadarPcd(pcd, &dropped);
  ASSERT_EQ(cloud.size() + dropped, 5u);
  for (std::size_t i = 0, k = 0; i < 5; ++i) {
    if (!std::isfinite(xs[i]) || !std::isfinite(ys[i])) continue;
    ASSERT_LT(k, cloud.size());
    EXPECT_EQ(cloud[k].x, xs[i]) << i;
    EXPECT_EQ(cloud[k].y, ys[i]) << i;
    ++k;
  }
  // The nuScenes reader: the garbled invalid_state field is absent (a keep list of a field the
  // data lacks keeps every detection) and no ambig_state is 3, so the devkit's keep list drops
  // every point; with no filter, every finite point is read at its place.
  NuScenesPcdStats stats;
  NuScenesRadarFilter devkit;
  devkit.ambig_states = {3};
  const auto filtered = readNuScenesRadarPcd(pcd, devkit, 0, &stats);
  EXPECT_EQ(stats.points_in_file, 5u);
  EXPECT_EQ(stats.kept + stats.dropped_by_filter + stats.dropped_non_finite, 5u);
  EXPECT_EQ(filtered.size(), stats.kept);
  EXPECT_TRUE(filtered.empty());
  NuScenesRadarFilter none;
  none.max_range = 1e30;
  none.invalid_states.clear();
  none.ambig_states.clear();
  NuScenesPcdStats all;
  const auto unfiltered = readNuScenesRadarPcd(pcd, none, 0, &all);
  EXPECT_EQ(all.dropped_by_filter, 0u);
  EXPECT_EQ(unfiltered.size() + all.dropped_non_finite, 5u);
  for (const auto& p : unfiltered)
    EXPECT_NE(std::find(xs.begin(), xs.end(), p.x), xs.end()) << "a point the file does not hold: " << p.x;
}

TEST(BadInput, DatasetsCannotPointTheReaderOutsideTheirFolder) {
  // nuScenes: a sample_data filename that is absolute or climbs out with '..' is refused, naming
  // the table and the row; a plain relative one is read.
  const std::string root = test::freshTempDir("escape_nuscenes");
  std::filesystem::create_directories(root + "/v1.0-test");
  auto tables = [&](const std::string& filename) {
    NuScenesTableWriter w;
    w.addLog("log", "log", "car", "2020-01-01", "here");
    w.addScene("scene", "log", 1, "s0", "s0", "scene-1", "");
    w.addSample("s0", 1000, "", "", "scene");
    w.addSensor("sensor", "RADAR_FRONT", "radar");
    w.addCalibratedSensor("cal", "sensor", {3.4, 0, 0.5}, {1, 0, 0, 0});
    w.addEgoPose("ego", 1000, {1, 0, 0, 0}, {0, 0, 0});
    w.addSampleData("sd", "s0", "ego", "cal", 1000, true, filename, "", "");
    w.write(root + "/v1.0-test");
  };
  tables("samples/RADAR_FRONT/a.pcd");
  ASSERT_NO_THROW(NuScenesDataset ds(root));
  for (const std::string bad :
       {"../outside.pcd", "samples/../../outside.pcd", "/etc/passwd", "samples/RADAR_FRONT/../../../x.pcd"}) {
    tables(bad);
    try {
      NuScenesDataset ds(root);
      ADD_FAILURE() << "accepted the filename " << bad;
    } catch (const IoError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("sample_data.json"), std::string::npos) << what;
      EXPECT_NE(what.find("row 0"), std::string::npos) << what;
      EXPECT_NE(what.find("leaves the dataroot"), std::string::npos) << what;
    }
  }

  // Oxford and RADIATE: the scan files are named from the index's numbers, so no index line can
  // name a file outside the sequence folder; lines that are not numbers are left out and reported.
  const std::string ox = test::freshTempDir("escape_oxford");
  writeAll(ox + "/radar.timestamps",
           "../../etc/passwd 1\n1547120000000000 1\n1547120000250000/../../x 1\n/tmp/x 1\n1547120000500000 1\n");
  const ScanningSequence oxford(ox, ScanFormat::Oxford);
  ASSERT_EQ(oxford.size(), 2u);
  EXPECT_EQ(oxford.indexProblems().size(), 3u);
  for (std::size_t k = 0; k < oxford.size(); ++k) {
    EXPECT_EQ(oxford.path(k).rfind(ox + "/radar/", 0), 0u) << oxford.path(k);
    EXPECT_EQ(oxford.path(k).find(".."), std::string::npos) << oxford.path(k);
  }
  const std::string ra = test::freshTempDir("escape_radiate");
  writeAll(
      ra + "/Navtech_Polar.txt",
      "Frame: ../../x Time: 1574859771.5\nFrame: 000001 Time: 1574859771.75\nFrame: /etc/passwd Time: 1574859772.0\n"
      "Frame: 000002 Time: 1574859772.0\n");
  const ScanningSequence radiate(ra, ScanFormat::Radiate);
  ASSERT_EQ(radiate.size(), 2u);
  EXPECT_EQ(radiate.indexProblems().size(), 2u);
  for (std::size_t k = 0; k < radiate.size(); ++k)
    EXPECT_EQ(radiate.path(k).rfind(ra + "/Navtech_Polar/", 0), 0u) << radiate.path(k);
}
