#include "navtech_rows.h"

#include <cmath>
#include <cstring>

#include "radar_ndt/io/io_error.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace detail {
namespace {

constexpr double kTwoPi = 2.0 * kPi;

std::int64_t readLe64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return static_cast<std::int64_t>(v);
}

}  // namespace

int navtechBins(const std::string& path, const GrayImage& img, int expected_bins, const char* dataset) {
  if (img.width <= kNavtechMetaBytes)
    throw IoError(path, "image is " + std::to_string(img.width) + " pixels wide: " + dataset +
                            " radar row needs 11 metadata bytes and the range bins");
  const int bins = img.width - kNavtechMetaBytes;
  if (expected_bins > 0 && bins != expected_bins)
    throw IoError(path, "image is " + std::to_string(img.width) + " pixels wide, expected " +
                            std::to_string(expected_bins + kNavtechMetaBytes) + " (11 metadata bytes + " +
                            std::to_string(expected_bins) + " range bins)");
  return bins;
}

void readNavtechRows(const std::string& path, const GrayImage& img, int encoder_size, const PolarConvention& convention,
                     PolarScan& scan) {
  scan.azimuths = img.height;
  scan.bins = img.width - kNavtechMetaBytes;
  scan.power.resize(static_cast<std::size_t>(scan.azimuths) * scan.bins);
  scan.angle.resize(scan.azimuths);
  scan.stamp_us.resize(scan.azimuths);
  scan.encoder.resize(scan.azimuths);
  for (int a = 0; a < scan.azimuths; ++a) {
    const std::uint8_t* row = img.pixels.data() + static_cast<std::size_t>(a) * img.width;
    scan.stamp_us[a] = readLe64(row);
    scan.encoder[a] = static_cast<std::uint16_t>(row[8] | (row[9] << 8));
    if (scan.encoder[a] >= encoder_size)
      throw IoError(path, "row " + std::to_string(a) + ": encoder count " + std::to_string(scan.encoder[a]) +
                              " outside [0, " + std::to_string(encoder_size) + ")");
    if (a > 0 && scan.stamp_us[a] < scan.stamp_us[a - 1])
      throw IoError(path, "row " + std::to_string(a) + ": azimuth timestamps out of order (" +
                              std::to_string(scan.stamp_us[a]) + " after " + std::to_string(scan.stamp_us[a - 1]) +
                              ")");
    scan.angle[a] = convention.toVehicleAngle(kTwoPi * scan.encoder[a] / encoder_size);
    std::memcpy(scan.row(a), row + kNavtechMetaBytes, static_cast<std::size_t>(scan.bins));
  }
}

void writeNavtechRows(const std::string& path, const PolarScan& scan, const PolarConvention& convention,
                      int encoder_size, const std::function<std::uint8_t(int)>& flag, int compression_level) {
  const int width = scan.bins + kNavtechMetaBytes;
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
    row[10] = flag(a);
    std::memcpy(row + kNavtechMetaBytes, scan.row(a), static_cast<std::size_t>(scan.bins));
  }
  writePng(path, width, scan.azimuths, 1, pixels.data(), compression_level);
}

}  // namespace detail
}  // namespace radar_ndt
