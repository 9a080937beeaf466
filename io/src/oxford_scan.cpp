#include "radar_ndt/io/oxford_scan.h"

#include <cstring>

#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/png_image.h"
#include "radar_ndt/se2.h"
#include "read_file.h"
#include "text_lines.h"

namespace radar_ndt {
namespace {

constexpr double kTwoPi = 2.0 * kPi;
constexpr int kOxfordMetaBytes = 11;  // int64 timestamp, uint16 encoder, uint8 flag

std::int64_t readLe64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return static_cast<std::int64_t>(v);
}
std::uint16_t readLe16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}

bool stemAsStamp(const std::string& path, std::int64_t& stamp) {
  const std::size_t slash = path.find_last_of('/');
  std::string stem = path.substr(slash == std::string::npos ? 0 : slash + 1);
  const std::size_t dot = stem.find('.');
  if (dot != std::string::npos) stem = stem.substr(0, dot);
  if (stem.empty() || stem.size() > 18) return false;
  for (char c : stem)
    if (c < '0' || c > '9') return false;
  stamp = std::stoll(stem);
  return true;
}

}  // namespace

PolarScan readOxfordPolarPng(const std::string& path, const OxfordPolarOptions& options) {
  thread_local GrayImage img;  // decoded scan after scan into the same storage
  readGrayPng(path, img);
  if (img.width <= kOxfordMetaBytes)
    throw IoError(path, "image is " + std::to_string(img.width) +
                            " pixels wide: an Oxford radar row needs 11 metadata bytes and the range bins");
  const int bins = img.width - kOxfordMetaBytes;
  if (options.expected_bins > 0 && bins != options.expected_bins)
    throw IoError(path, "image is " + std::to_string(img.width) + " pixels wide, expected " +
                            std::to_string(options.expected_bins + kOxfordMetaBytes) + " (11 metadata bytes + " +
                            std::to_string(options.expected_bins) + " range bins)");
  if (options.encoder_size <= 0) throw IoError(path, "encoder_size must be positive");
  PolarScan scan;
  scan.azimuths = img.height;
  scan.bins = bins;
  scan.range_resolution = options.convention.range_resolution;
  scan.range_offset_bins = options.convention.range_offset_bins;
  scan.power.resize(static_cast<std::size_t>(scan.azimuths) * bins);
  scan.angle.resize(scan.azimuths);
  scan.stamp_us.resize(scan.azimuths);
  scan.measured.resize(scan.azimuths);
  scan.encoder.resize(scan.azimuths);
  for (int a = 0; a < scan.azimuths; ++a) {
    const std::uint8_t* row = img.pixels.data() + static_cast<std::size_t>(a) * img.width;
    scan.stamp_us[a] = readLe64(row);
    scan.encoder[a] = readLe16(row + 8);
    scan.measured[a] = row[10] == 255;
    if (scan.encoder[a] >= options.encoder_size)
      throw IoError(path, "row " + std::to_string(a) + ": encoder count " + std::to_string(scan.encoder[a]) +
                              " outside [0, " + std::to_string(options.encoder_size) + ")");
    if (a > 0 && scan.stamp_us[a] < scan.stamp_us[a - 1])
      throw IoError(path, "row " + std::to_string(a) + ": azimuth timestamps out of order (" +
                              std::to_string(scan.stamp_us[a]) + " after " + std::to_string(scan.stamp_us[a - 1]) +
                              ")");
    scan.angle[a] = options.convention.toVehicleAngle(kTwoPi * scan.encoder[a] / options.encoder_size);
    std::memcpy(scan.row(a), row + kOxfordMetaBytes, static_cast<std::size_t>(bins));
  }
  if (!stemAsStamp(path, scan.stamp)) scan.stamp = scan.stamp_us.front();
  return scan;
}

void writeOxfordPolarPng(const std::string& path, const PolarScan& scan, const OxfordPolarOptions& options,
                         int compression_level) {
  if (scan.azimuths <= 0 || scan.bins <= 0 ||
      scan.power.size() != static_cast<std::size_t>(scan.azimuths) * scan.bins ||
      scan.angle.size() != static_cast<std::size_t>(scan.azimuths) ||
      scan.stamp_us.size() != static_cast<std::size_t>(scan.azimuths))
    throw IoError(path, "inconsistent PolarScan (sizes of power, angle and stamp_us do not match)");
  const int width = scan.bins + kOxfordMetaBytes;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * scan.azimuths);
  for (int a = 0; a < scan.azimuths; ++a) {
    std::uint8_t* row = pixels.data() + static_cast<std::size_t>(a) * width;
    const auto t = static_cast<std::uint64_t>(scan.stamp_us[a]);
    for (int i = 0; i < 8; ++i) row[i] = static_cast<std::uint8_t>(t >> (8 * i));
    int enc = scan.encoder.size() == static_cast<std::size_t>(scan.azimuths)
                  ? scan.encoder[a]
                  : static_cast<int>(
                        std::lround(options.convention.toSensorAzimuth(scan.angle[a]) / kTwoPi * options.encoder_size));
    enc %= options.encoder_size;
    row[8] = static_cast<std::uint8_t>(enc & 0xff);
    row[9] = static_cast<std::uint8_t>((enc >> 8) & 0xff);
    row[10] = scan.measured.empty() || scan.measured[a] ? 255 : 0;
    std::memcpy(row + kOxfordMetaBytes, scan.row(a), static_cast<std::size_t>(scan.bins));
  }
  writePng(path, width, scan.azimuths, 1, pixels.data(), compression_level);
}

namespace {

// One index line: `<timestamp µs> <valid>`, its timestamp after the previous line's.
OxfordStamp parseStampLine(const std::string& path, std::size_t n, const std::string& line,
                           const std::vector<OxfordStamp>& before) {
  std::istringstream ss(line);
  std::string t, v, extra;
  ss >> t;
  if (!(ss >> v) || (ss >> extra)) throw IoError(path, n, "expected '<timestamp> <valid>', found '" + line + "'");
  OxfordStamp s;
  s.stamp = detail::parseInt64(path, n, t, "timestamp");
  const std::int64_t valid = detail::parseInt64(path, n, v, "valid flag");
  if (valid != 0 && valid != 1) throw IoError(path, n, "valid flag must be 0 or 1, found " + v);
  s.valid = valid == 1;
  if (!before.empty() && s.stamp <= before.back().stamp)
    throw IoError(path, n,
                  std::string(s.stamp == before.back().stamp ? "duplicated timestamp" : "timestamps out of order") +
                      " (" + t + " after " + std::to_string(before.back().stamp) + ")");
  return s;
}

}  // namespace

std::vector<OxfordStamp> readOxfordTimestamps(const std::string& path, std::vector<IoError>* skipped) {
  return detail::readIndexLines<OxfordStamp>(path, skipped,
                                             [&](std::size_t n, const std::string& line, const auto& so_far) {
                                               return parseStampLine(path, n, line, so_far);
                                             });
}

void writeOxfordTimestamps(const std::string& path, const std::vector<OxfordStamp>& stamps) {
  std::string s;
  for (const auto& t : stamps) s += std::to_string(t.stamp) + (t.valid ? " 1\n" : " 0\n");
  writeFileAtomically(path, s);
}

}  // namespace radar_ndt
