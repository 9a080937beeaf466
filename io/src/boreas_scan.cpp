#include "radar_ndt/io/boreas_scan.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "navtech_rows.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/png_image.h"

namespace radar_ndt {
namespace {

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
    const std::uint8_t f = detail::navtechFlag(img, a);
    if (f != 0 && f != 255) return false;
    if (a > 0 && f == detail::navtechFlag(img, a - 1)) return false;
  }
  return true;
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
  checkFields(*this, "BoreasPolarOptions");
}

PolarScan readBoreasPolarPng(const std::string& path, const BoreasPolarOptions& options) {
  options.validate();
  thread_local GrayImage img;  // decoded scan after scan into the same storage
  readGrayPng(path, img);
  const int bins = detail::navtechBins(path, img, options.expected_bins, "a Boreas");
  const std::string stem = stemOf(path);
  double name_time_s = 0;
  const bool named = boreasTimeSeconds(stem, &name_time_s);
  PolarScan scan;
  // The SDK decides the bin by the file name's time (0 when the name is not a time: the older bin).
  scan.range_resolution =
      options.range_resolution > 0 ? options.range_resolution : boreasRangeResolution(named ? name_time_s : 0.0);
  scan.range_offset_bins = options.range_offset_bins;
  const PolarConvention convention{scan.range_resolution, options.range_offset_bins, 0.0, true};
  detail::readNavtechRows(path, img, options.encoder_size, convention, scan);
  const bool chirps =
      options.flag == BoreasFlag::ChirpType || (options.flag == BoreasFlag::Auto && looksLikeChirpTypes(img));
  scan.measured.assign(scan.azimuths, 1);
  if (chirps) scan.chirp_up.resize(scan.azimuths);
  for (int a = 0; a < scan.azimuths; ++a)
    (chirps ? scan.chirp_up[a] : scan.measured[a]) = detail::navtechFlag(img, a) == 255;
  // The SDK zeroes the bins under round(zero_below / resolution).
  const int zeroed = std::min(bins, static_cast<int>(std::lround(options.zero_below / scan.range_resolution)));
  for (int a = 0; a < scan.azimuths; ++a) std::memset(scan.row(a), 0, static_cast<std::size_t>(zeroed));
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
  detail::writeNavtechRows(
      path, scan, convention, encoder_size,
      [&](int a) -> std::uint8_t {
        const bool set = scan.chirp_up.empty() ? (scan.measured.empty() || scan.measured[a]) : scan.chirp_up[a] != 0;
        return set ? 255 : 0;
      },
      compression_level);
}

}  // namespace radar_ndt
