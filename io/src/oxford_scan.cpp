#include "radar_ndt/io/oxford_scan.h"

#include <cstring>

#include "navtech_rows.h"
#include "radar_ndt/io/atomic_file.h"
#include "radar_ndt/io/png_image.h"
#include "radar_ndt/se2.h"
#include "read_file.h"
#include "text_lines.h"

namespace radar_ndt {
namespace {

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
  detail::navtechBins(path, img, options.expected_bins, "an Oxford");
  if (options.encoder_size <= 0) throw IoError(path, "encoder_size must be positive");
  PolarScan scan;
  scan.range_resolution = options.convention.range_resolution;
  scan.range_offset_bins = options.convention.range_offset_bins;
  detail::readNavtechRows(path, img, options.encoder_size, options.convention, scan);
  scan.measured.resize(scan.azimuths);
  for (int a = 0; a < scan.azimuths; ++a) scan.measured[a] = detail::navtechFlag(img, a) == 255;
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
  detail::writeNavtechRows(
      path, scan, options.convention, options.encoder_size,
      [&](int a) -> std::uint8_t { return scan.measured.empty() || scan.measured[a] ? 255 : 0; }, compression_level);
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
