// Polar scan readers: real RADIATE scans, Oxford files written by the simulator (round trip), and
// malformed files that must fail with a message naming the file and the problem.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "png_support.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/oxford_ground_truth.h"
#include "radar_ndt/io/oxford_scan.h"
#include "radar_ndt/io/png_image.h"
#include "radar_ndt/io/polar_scan.h"
#include "radar_ndt/io/radiate_scan.h"
#include "radar_ndt/sim/radar_sim.h"
#include "test_support.h"

using namespace radar_ndt;
using radar_ndt::test::buildPng;
using radar_ndt::test::freshTempDir;
using radar_ndt::test::pngChunk;
using radar_ndt::test::readBytes;
using radar_ndt::test::writeBytes;
namespace fs = std::filesystem;

namespace {

const std::string kRadiate = std::string(RADAR_NDT_SHARED_DATA) + "/radiate-tiny-foggy";

/// Expects `f` to throw an IoError whose message names `path` and contains `what`.
template <typename F>
void expectIoError(F f, const std::string& path, const std::string& what) {
  try {
    f();
    ADD_FAILURE() << "no error for " << path << " (expected '" << what << "')";
  } catch (const IoError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

/// A small Oxford-format scan with known content.
PolarScan smallOxfordScan(int azimuths = 400, int bins = 3768) {
  PolarScan s;
  s.azimuths = azimuths;
  s.bins = bins;
  s.range_resolution = 0.0438;
  s.range_offset_bins = 0.5;
  s.power.resize(static_cast<std::size_t>(azimuths) * bins);
  for (std::size_t i = 0; i < s.power.size(); ++i) s.power[i] = static_cast<std::uint8_t>((i * 7) % 251);
  const OxfordPolarOptions o;
  for (int a = 0; a < azimuths; ++a) {
    s.encoder.push_back(static_cast<std::uint16_t>(a * o.encoder_size / azimuths));
    s.angle.push_back(o.convention.toVehicleAngle(2 * kPi * s.encoder.back() / o.encoder_size));
    s.stamp_us.push_back(1547120000000000 + a * 625);
    s.measured.push_back(a % 50 == 7 ? 0 : 1);
  }
  s.stamp = s.stamp_us.front();
  return s;
}

}  // namespace

TEST(PolarConvention, OxfordAzimuthsTurnClockwiseFromTheFront) {
  const PolarConvention c = OxfordPolarOptions().convention;
  EXPECT_NEAR(c.toVehicleAngle(0.0), 0.0, 1e-12);
  EXPECT_NEAR(c.toVehicleAngle(kPi / 2), -kPi / 2, 1e-12);  // a quarter turn clockwise: the right side (−y)
  EXPECT_NEAR(std::abs(c.toVehicleAngle(kPi)), kPi, 1e-12);
  for (double a : {0.0, 0.3, 2.0, 4.0, 6.0}) EXPECT_NEAR(c.toSensorAzimuth(c.toVehicleAngle(a)), a, 1e-9);
  PolarConvention ccw{0.1, 0.0, 0.5, false};
  EXPECT_NEAR(ccw.toVehicleAngle(0.25), 0.75, 1e-12);
}

TEST(RadiatePolar, RealScansHaveTheDatasetLayout) {
  if (!fs::exists(kRadiate + "/Navtech_Polar.txt"))
    GTEST_SKIP() << "no " << kRadiate << " (../shared/data is absent): skipping the real-data check";
  const auto frames = readRadiateFrameTimes(kRadiate + "/Navtech_Polar.txt");
  ASSERT_GE(frames.size(), 18u);
  EXPECT_EQ(frames[0].frame, 1);
  EXPECT_EQ(frames[0].stamp_us, 1574859771744660);  // "1574859771.744660272" truncated to µs
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const double dt = (frames[i].stamp_us - frames[i - 1].stamp_us) * 1e-6;
    EXPECT_GT(dt, 0.15);  // ~4 Hz
    EXPECT_LT(dt, 0.4);
  }
  const PolarScan s = readRadiatePolarPng(kRadiate + "/Navtech_Polar/000001.png", frames[0].stamp_us);
  EXPECT_EQ(s.azimuths, 400);
  EXPECT_EQ(s.bins, 576);
  EXPECT_DOUBLE_EQ(s.range_resolution, 0.173611);
  EXPECT_NEAR(s.maxRange(), 575 * 0.173611, 1e-9);
  EXPECT_NEAR(s.angle[0], 0.0, 1e-12);
  EXPECT_NEAR(s.angle[100], -kPi / 2, 1e-12);  // clockwise, as every Navtech
  EXPECT_EQ(s.stamp, frames[0].stamp_us);
  EXPECT_EQ(s.stamp_us.front(), frames[0].stamp_us);
  EXPECT_NEAR((s.stamp_us.back() - s.stamp_us.front()) * 1e-6, 0.25 * 399 / 400, 1e-5);
  for (int a = 1; a < s.azimuths; ++a) EXPECT_GE(s.stamp_us[a], s.stamp_us[a - 1]);
  // Real data: mostly dark noise floor, some bright returns.
  double mean = 0;
  int bright = 0;
  for (auto v : s.power) {
    mean += v;
    bright += v > 128;
  }
  mean /= s.power.size();
  EXPECT_GT(mean, 5.0);
  EXPECT_LT(mean, 60.0);
  EXPECT_GT(bright, 10);
}

TEST(RadiatePolar, WrongAzimuthCountIsAnError) {
  const std::string dir = freshTempDir("radiate_width");
  const std::string path = dir + "/000001.png";
  std::vector<std::uint8_t> px(399 * 576, 10);
  writePng(path, 399, 576, 1, px.data());
  expectIoError([&] { readRadiatePolarPng(path); }, path, "399 pixels wide, expected 400");
  fs::remove_all(dir);
}

TEST(OxfordPolar, WriteReadRoundTrip) {
  const std::string dir = freshTempDir("oxford_rt");
  const std::string path = dir + "/1547120000000000.png";
  const PolarScan s = smallOxfordScan();
  writeOxfordPolarPng(path, s);
  const PolarScan r = readOxfordPolarPng(path);
  EXPECT_EQ(r.azimuths, 400);
  EXPECT_EQ(r.bins, 3768);
  EXPECT_EQ(r.power, s.power);
  EXPECT_EQ(r.encoder, s.encoder);
  EXPECT_EQ(r.stamp_us, s.stamp_us);
  EXPECT_EQ(r.measured, s.measured);
  EXPECT_EQ(r.stamp, 1547120000000000);
  for (int a = 0; a < 400; ++a) EXPECT_NEAR(r.angle[a], s.angle[a], 1e-12);
  EXPECT_DOUBLE_EQ(r.range_resolution, 0.0438);
  EXPECT_NEAR(r.rangeOf(0), 0.5 * 0.0438, 1e-12);
  // The SDK's resolution is a setting.
  OxfordPolarOptions sdk;
  sdk.convention.range_resolution = 0.0432;
  EXPECT_DOUBLE_EQ(readOxfordPolarPng(path, sdk).range_resolution, 0.0432);
  fs::remove_all(dir);
}

TEST(OxfordPolar, MalformedFilesGiveClearErrors) {
  const std::string dir = freshTempDir("oxford_bad");
  const std::string good = dir + "/1547120000000000.png";
  writeOxfordPolarPng(good, smallOxfordScan());
  const std::string bytes = readBytes(good);

  const std::string text = dir + "/not_png.png";
  writeBytes(text, "timestamp,x,y\n1,2,3\n");
  expectIoError([&] { readOxfordPolarPng(text); }, text, "not a PNG");

  const std::string empty = dir + "/empty.png";
  writeBytes(empty, "");
  expectIoError([&] { readOxfordPolarPng(empty); }, empty, "empty file");

  const std::string truncated = dir + "/truncated.png";
  writeBytes(truncated, bytes.substr(0, bytes.size() / 2));
  expectIoError([&] { readOxfordPolarPng(truncated); }, truncated, "truncated");

  const std::string header_only = dir + "/header_only.png";
  writeBytes(header_only, bytes.substr(0, 20));
  expectIoError([&] { readOxfordPolarPng(header_only); }, header_only, "PNG");

  const std::string narrow = dir + "/narrow.png";
  std::vector<std::uint8_t> px(400 * 600, 0);
  writePng(narrow, 600, 400, 1, px.data());
  expectIoError([&] { readOxfordPolarPng(narrow); }, narrow, "600 pixels wide");

  const std::string colour = dir + "/colour.png";
  std::vector<std::uint8_t> rgb(400 * 3779 * 3, 0);
  rgb[3 * 5000 + 1] = 1;  // one pixel not grey
  writePng(colour, 3779, 400, 3, rgb.data());
  expectIoError([&] { readOxfordPolarPng(colour); }, colour, "colour image (pixel 1221, 1 is RGB 0,1,0)");

  PolarScan backwards = smallOxfordScan();
  backwards.stamp_us[200] = backwards.stamp_us[100];
  const std::string order = dir + "/order.png";
  writeOxfordPolarPng(order, backwards);
  expectIoError([&] { readOxfordPolarPng(order); }, order, "out of order");

  const std::string missing = dir + "/missing.png";
  expectIoError([&] { readOxfordPolarPng(missing); }, missing, "cannot open");
  fs::remove_all(dir);
}

TEST(OxfordPolar, ScansWrittenByOtherToolsReadAsTheirStoredValues) {
  // The samples are data, not a picture: a gAMA chunk (which libpng's simplified API applies to
  // 8-bit output), a grey image stored as RGB, RGBA, grey + alpha or through a grey palette, and
  // interlacing must all give the stored bytes. Real colour and other sample depths are refused.
  const std::string dir = freshTempDir("oxford_tools");
  const std::string plain = dir + "/1547120000000000.png";
  writeOxfordPolarPng(plain, smallOxfordScan(40));
  const GrayImage img = readGrayPng(plain);
  const PolarScan ref = readOxfordPolarPng(plain);
  const int w = img.width, h = img.height;
  const std::vector<std::uint8_t>& g = img.pixels;
  std::vector<std::uint8_t> rgb, rgba, ga, g16;
  for (std::uint8_t v : g) {
    rgb.insert(rgb.end(), {v, v, v});
    rgba.insert(rgba.end(), {v, v, v, 255});
    ga.insert(ga.end(), {v, 255});
    g16.insert(g16.end(), {v, v});
  }
  std::string grey_palette;
  for (int i = 0; i < 256; ++i) grey_palette += std::string(3, static_cast<char>(i));
  const std::string gamma_linear = pngChunk("gAMA", std::string("\x00\x01\x86\xa0", 4));  // 1.0
  const std::vector<std::pair<std::string, std::string>> same = {
      {"gamma_1.png", buildPng(w, h, 8, 0, 1, g, gamma_linear)},
      {"srgb.png", buildPng(w, h, 8, 0, 1, g, pngChunk("sRGB", std::string(1, '\0')))},
      {"rgb.png", buildPng(w, h, 8, 2, 3, rgb)},
      {"rgba.png", buildPng(w, h, 8, 6, 4, rgba, gamma_linear)},
      {"grey_alpha.png", buildPng(w, h, 8, 4, 2, ga)},
      {"palette.png", buildPng(w, h, 8, 3, 1, g, pngChunk("PLTE", grey_palette))},
      {"adam7.png", buildPng(w, h, 8, 0, 1, g, "", true)},
  };
  for (const auto& [name, bytes] : same) {
    const std::string path = dir + "/" + name;
    writeBytes(path, bytes);
    try {
      const PolarScan r = readOxfordPolarPng(path);
      EXPECT_EQ(r.power, ref.power) << name;
      EXPECT_EQ(r.stamp_us, ref.stamp_us) << name;
      EXPECT_EQ(r.encoder, ref.encoder) << name;
      EXPECT_EQ(r.measured, ref.measured) << name;
    } catch (const std::exception& e) {
      ADD_FAILURE() << name << ": " << e.what();
    }
  }
  std::vector<std::uint8_t> tinted = rgb;
  tinted[3 * (2 * w + 100) + 2] ^= 1;
  const std::string colour = dir + "/colour.png";
  writeBytes(colour, buildPng(w, h, 8, 2, 3, tinted));
  expectIoError([&] { readOxfordPolarPng(colour); }, colour, "colour image (pixel 100, 2");
  const std::string deep = dir + "/16bit.png";
  writeBytes(deep, buildPng(w, h, 16, 0, 2, g16));
  expectIoError([&] { readOxfordPolarPng(deep); }, deep, "16-bit samples");
  fs::remove_all(dir);
}

TEST(OxfordSequenceFiles, TimestampsAndOdometryCsvErrors) {
  const std::string dir = freshTempDir("oxford_csv");
  const std::string ts = dir + "/radar.timestamps";
  writeBytes(ts, "1547120000000000 1\n1547120000250000 1\n1547120000200000 1\n");
  expectIoError([&] { readOxfordTimestamps(ts); }, ts, "out of order");
  writeBytes(ts, "1547120000000000 1\n1547120000250000 2\n");
  expectIoError([&] { readOxfordTimestamps(ts); }, ts, "valid flag");
  writeBytes(ts, "1547120000000000 1\nabc 1\n");
  expectIoError([&] { readOxfordTimestamps(ts); }, ts, ":2");

  const std::string csv = dir + "/radar_odometry.csv";
  const std::string header =
      "source_timestamp,destination_timestamp,x,y,z,roll,pitch,yaw,source_radar_timestamp,destination_radar_"
      "timestamp\n";
  writeBytes(csv, "source_timestamp,destination_timestamp,x,y,z,roll,pitch\n");
  expectIoError([&] { readOxfordRadarOdometry(csv); }, csv, "no column 'yaw'");
  writeBytes(csv, header + "2,1,0.5,0,0,0,0,0.01,2,1\n4,3,0.5,0,0,0,0,0.01,4,3\n");
  expectIoError([&] { readOxfordRadarOdometry(csv); }, csv, "does not chain");
  writeBytes(csv, header + "2,1,0.5,0,0,0,0\n");
  expectIoError([&] { readOxfordRadarOdometry(csv); }, csv, "columns");
  writeBytes(csv, header + "2,1,nan,0,0,0,0,0.01,2,1\n");
  expectIoError([&] { readOxfordRadarOdometry(csv); }, csv, "not finite");
  // Any column order, by name.
  writeBytes(csv, "yaw,x,y,z,roll,pitch,destination_timestamp,source_timestamp\n0.01,0.5,-0.1,0,0,0,1,2\n");
  const auto rows = readOxfordRadarOdometry(csv);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].source, 2);
  EXPECT_EQ(rows[0].destination, 1);
  EXPECT_DOUBLE_EQ(rows[0].x, 0.5);
  EXPECT_DOUBLE_EQ(rows[0].y, -0.1);
  EXPECT_DOUBLE_EQ(rows[0].yaw, 0.01);
  fs::remove_all(dir);
}
