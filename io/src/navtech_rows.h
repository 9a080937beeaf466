#pragma once
// Internal to RadarNDT::io: the row layout Oxford Radar RobotCar and Boreas share (one row per
// azimuth: an 8-byte little-endian timestamp in µs, a 2-byte encoder count, one flag byte, then
// the range bins), read and written in one place for both datasets' readers and writers.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "radar_ndt/io/png_image.h"
#include "radar_ndt/io/polar_scan.h"

namespace radar_ndt {
namespace detail {

constexpr int kNavtechMetaBytes = 11;  // int64 timestamp, uint16 encoder, uint8 flag

/// The range bins of `img`'s rows; throws IoError naming the file when a row has no room for the
/// metadata or (expected_bins > 0) another count. `dataset`: "an Oxford", "a Boreas" (in messages).
int navtechBins(const std::string& path, const GrayImage& img, int expected_bins, const char* dataset);

/// Fills `scan`'s azimuths, bins, power, per-azimuth timestamps, encoder counts and vehicle-frame
/// angles (by `convention`) from `img`'s rows; the flag bytes are the caller's (navtechFlag).
/// Throws IoError naming the file and row for an encoder count outside [0, encoder_size) or a
/// timestamp before the previous row's.
void readNavtechRows(const std::string& path, const GrayImage& img, int encoder_size, const PolarConvention& convention,
                     PolarScan& scan);

/// Row a's flag byte.
inline std::uint8_t navtechFlag(const GrayImage& img, int a) {
  return img.pixels[static_cast<std::size_t>(a) * img.width + 10];
}

/// Writes `scan` in the shared layout (encoder counts as stored, or from the angles by
/// `convention`; row a's flag byte `flag(a)`), atomically.
void writeNavtechRows(const std::string& path, const PolarScan& scan, const PolarConvention& convention,
                      int encoder_size, const std::function<std::uint8_t(int)>& flag, int compression_level);

}  // namespace detail
}  // namespace radar_ndt
