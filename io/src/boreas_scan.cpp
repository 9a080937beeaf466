#include "radar_ndt/io/boreas_scan.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/png_image.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace {

constexpr double kTwoPi = 2.0 * kPi;
constexpr int kMetaBytes = 11;  // int64 timestamp, uint16 encoder, uint8 flag (Oxford's layout)

std::int64_t readLe64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return static_cast<std::int64_t>(v);
}

std::string stemOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  std::string stem = path.substr(slash == std::string::npos ? 0 : slash + 1);
  const std::size_t dot = stem.rfind('.');
  return dot == std::string::npos ? stem : stem.substr(0, dot);
}

// 1 to 19 digits that fit an int64 (the largest time token is 19 digits of nanoseconds).
bool allDigits(const std::string& token) {
  if (token.empty() || token.size() > 19) return false;
  for (char c : token)
    if (c < '0' || c > '9') return false;
  return token.size() < 19 || token <= "9223372036854775807";
}

// Chirp types when the flag byte alternates between 0 and 255 from row to row (the SDK has no
// reliable date for it: the chirp-type time in metadata_splits.py is after real chirp scans).
bool looksLikeChirpTypes(const GrayImage& img) {
  if (img.height < 2) return false;
  for (int a = 0; a < img.height; ++a) {
    const std::uint8_t f = img.pixels[static_cast<std::size_t>(a) * img.width + 10];
    if (f != 0 && f != 255) return false;
    if (a > 0 && f == img.pixels[static_cast<std::size_t>(a - 1) * img.width + 10]) return false;
  }
  return true;
}

void checkWidth(const std::string& path, const GrayImage& img, const BoreasPolarOptions& options) {
  if (img.width <= kMetaBytes)
    throw IoError(path, "image is " + std::to_string(img.width) +
                            " pixels wide: a Boreas radar row needs 11 metadata bytes and the range bins");
  const int bins = img.width - kMetaBytes;
  if (options.expected_bins > 0 && bins != options.expected_bins)
    throw IoError(path, "image is " + std::to_string(img.width) + " pixels wide, expected " +
                            std::to_string(options.expected_bins + kMetaBytes) + " (11 metadata bytes + " +
                            std::to_string(options.expected_bins) + " range bins)");
}

}  // namespace

bool boreasTimeSeconds(const std::string& token, double* seconds) {
  if (!allDigits(token)) return false;
  const double value = std::stod(token);
  const std::size_t n = token.size();
  double scale = 1e-6;  // 16 digits: microseconds
  if (n != 16) scale = n > 10 ? std::pow(10.0, -static_cast<double>(n - 10)) : 1.0;
  *seconds = value * scale;
  return true;
}

bool boreasTimeMicros(const std::string& token, std::int64_t* micros) {
  if (!allDigits(token)) return false;
  const std::int64_t value = std::stoll(token);
  const std::size_t n = token.size();
  if (n == 16) {
    *micros = value;
  } else if (n > 16) {
    std::int64_t divisor = 1;
    for (std::size_t i = 16; i < n; ++i) divisor *= 10;
    *micros = value / divisor;
  } else {  // 11 to 15 digits: 10^(n − 10) per second; 10 or fewer: seconds
    std::int64_t factor = 1;
    for (std::size_t i = n > 10 ? n : 10; i < 16; ++i) factor *= 10;
    *micros = value * factor;
  }
  return true;
}

double boreasRangeResolution(double time_s) {
  // pyboreas: `if t > radar_resolution_upgrade_time: resolution = 0.04381`.
  return time_s > kBoreasResolutionUpgradeTime ? kBoreasBinAfterUpgrade : kBoreasBinBeforeUpgrade;
}

void BoreasPolarOptions::validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("BoreasPolarOptions: " + what); };
  if (!(range_resolution >= 0) || !std::isfinite(range_resolution))
    fail("range_resolution must be >= 0 (0: by the scan's date)");
  if (!std::isfinite(range_offset_bins)) fail("range_offset_bins must be finite");
  if (!(zero_below >= 0) || !std::isfinite(zero_below)) fail("zero_below must be >= 0");
  if (encoder_size < 1) fail("encoder_size must be >= 1");
  if (expected_bins < 0) fail("expected_bins must be >= 0 (0: any width)");
}

PolarScan readBoreasPolarPng(const std::string& path, const BoreasPolarOptions& options) {
  options.validate();
  thread_local GrayImage img;  // decoded scan after scan into the same storage
  readGrayPng(path, img);
  checkWidth(path, img, options);
  const std::string stem = stemOf(path);
  double name_time_s = 0;
  const bool named = boreasTimeSeconds(stem, &name_time_s);
  PolarScan scan;
  scan.azimuths = img.height;
  scan.bins = img.width - kMetaBytes;
  // The SDK decides the bin by the file name's time (0 when the name is not a time: the older bin).
  scan.range_resolution =
      options.range_resolution > 0 ? options.range_resolution : boreasRangeResolution(named ? name_time_s : 0.0);
  scan.range_offset_bins = options.range_offset_bins;
  const bool chirps =
      options.flag == BoreasFlag::ChirpType || (options.flag == BoreasFlag::Auto && looksLikeChirpTypes(img));
  const PolarConvention convention{scan.range_resolution, options.range_offset_bins, 0.0, true};
  const int zeroed = std::min(scan.bins, static_cast<int>(std::lround(options.zero_below / scan.range_resolution)));
  scan.power.resize(static_cast<std::size_t>(scan.azimuths) * scan.bins);
  scan.angle.resize(scan.azimuths);
  scan.stamp_us.resize(scan.azimuths);
  scan.measured.assign(scan.azimuths, 1);
  scan.encoder.resize(scan.azimuths);
  if (chirps) scan.chirp_up.resize(scan.azimuths);
  for (int a = 0; a < scan.azimuths; ++a) {
    const std::uint8_t* row = img.pixels.data() + static_cast<std::size_t>(a) * img.width;
    scan.stamp_us[a] = readLe64(row);
    scan.encoder[a] = static_cast<std::uint16_t>(row[8] | (row[9] << 8));
    if (chirps)
      scan.chirp_up[a] = row[10] == 255;
    else
      scan.measured[a] = row[10] == 255;
    if (scan.encoder[a] >= options.encoder_size)
      throw IoError(path, "row " + std::to_string(a) + ": encoder count " + std::to_string(scan.encoder[a]) +
                              " outside [0, " + std::to_string(options.encoder_size) + ")");
    if (a > 0 && scan.stamp_us[a] < scan.stamp_us[a - 1])
      throw IoError(path, "row " + std::to_string(a) + ": azimuth timestamps out of order (" +
                              std::to_string(scan.stamp_us[a]) + " after " + std::to_string(scan.stamp_us[a - 1]) +
                              ")");
    scan.angle[a] = convention.toVehicleAngle(kTwoPi * scan.encoder[a] / options.encoder_size);
    std::uint8_t* out = scan.row(a);
    std::memcpy(out, row + kMetaBytes, static_cast<std::size_t>(scan.bins));
    std::memset(out, 0, static_cast<std::size_t>(zeroed));
  }
  std::int64_t name_us = 0;
  if (named && boreasTimeMicros(stem, &name_us))
    scan.stamp = name_us;
  else  // the dataset's name is row floor(M / 2) − 1's timestamp
    scan.stamp = scan.stamp_us[static_cast<std::size_t>(std::max(0, scan.azimuths / 2 - 1))];
  return scan;
}

void writeBoreasPolarPng(const std::string& path, const PolarScan& scan, int encoder_size, int compression_level) {
  if (scan.azimuths <= 0 || scan.bins <= 0 ||
      scan.power.size() != static_cast<std::size_t>(scan.azimuths) * scan.bins ||
      scan.angle.size() != static_cast<std::size_t>(scan.azimuths) ||
      scan.stamp_us.size() != static_cast<std::size_t>(scan.azimuths) ||
      (!scan.chirp_up.empty() && scan.chirp_up.size() != static_cast<std::size_t>(scan.azimuths)))
    throw IoError(path, "inconsistent PolarScan (sizes of power, angle, stamp_us and chirp_up do not match)");
  const PolarConvention convention{scan.range_resolution, scan.range_offset_bins, 0.0, true};
  const int width = scan.bins + kMetaBytes;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * scan.azimuths);
  for (int a = 0; a < scan.azimuths; ++a) {
    std::uint8_t* row = pixels.data() + static_cast<std::size_t>(a) * width;
    const auto t = static_cast<std::uint64_t>(scan.stamp_us[a]);
    for (int i = 0; i < 8; ++i) row[i] = static_cast<std::uint8_t>(t >> (8 * i));
    int enc = scan.encoder.size() == static_cast<std::size_t>(scan.azimuths)
                  ? scan.encoder[a]
                  : static_cast<int>(std::lround(convention.toSensorAzimuth(scan.angle[a]) / kTwoPi * encoder_size));
    enc %= encoder_size;
    row[8] = static_cast<std::uint8_t>(enc & 0xff);
    row[9] = static_cast<std::uint8_t>((enc >> 8) & 0xff);
    const bool flag = scan.chirp_up.empty() ? (scan.measured.empty() || scan.measured[a]) : scan.chirp_up[a] != 0;
    row[10] = flag ? 255 : 0;
    std::memcpy(row + kMetaBytes, scan.row(a), static_cast<std::size_t>(scan.bins));
  }
  writePng(path, width, scan.azimuths, 1, pixels.data(), compression_level);
}

}  // namespace radar_ndt
