#include "radar_ndt/io/radiate_scan.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "radar_ndt/io/png_image.h"
#include "radar_ndt/se2.h"
#include "read_file.h"
#include "text_lines.h"

namespace radar_ndt {
namespace {

constexpr double kTwoPi = 2.0 * kPi;

}  // namespace

PolarScan readRadiatePolarPng(const std::string& path, std::int64_t frame_time_us, const RadiatePolarOptions& options) {
  thread_local GrayImage img;  // decoded scan after scan into the same storage
  readGrayPng(path, img);
  if (options.expected_azimuths > 0 && img.width != options.expected_azimuths)
    throw IoError(path, "image is " + std::to_string(img.width) + " pixels wide, expected " +
                            std::to_string(options.expected_azimuths) + " azimuth columns");
  PolarScan scan;
  scan.azimuths = img.width;
  scan.bins = img.height;
  scan.range_resolution = options.convention.range_resolution;
  scan.range_offset_bins = options.convention.range_offset_bins;
  scan.stamp = frame_time_us;
  scan.power.resize(static_cast<std::size_t>(scan.azimuths) * scan.bins);
  scan.angle.resize(scan.azimuths);
  scan.stamp_us.resize(scan.azimuths);
  scan.measured.assign(scan.azimuths, 1);
  const double period_us = options.sweep_period * 1e6;
  for (int a = 0; a < scan.azimuths; ++a) {
    scan.angle[a] = options.convention.toVehicleAngle(kTwoPi * a / scan.azimuths);
    scan.stamp_us[a] = frame_time_us + static_cast<std::int64_t>(std::llround(period_us * a / scan.azimuths));
    std::uint8_t* dst = scan.row(a);
    for (int b = 0; b < scan.bins; ++b) dst[b] = img.pixels[static_cast<std::size_t>(b) * img.width + a];
  }
  return scan;
}

namespace {

// `Frame: <n> Time: <seconds>`: the frame number 0..999999, the time in whole microseconds (up to 9
// decimals, split at the dot so none is lost), after the previous line's.
RadiateFrame parseFrameLine(const std::string& path, std::size_t n, const std::string& line,
                            const std::vector<RadiateFrame>& before) {
  std::istringstream ss(line);
  std::string kf, f, kt, t;
  if (!(ss >> kf) || kf != "Frame:" || !(ss >> f >> kt >> t) || kt != "Time:")
    throw IoError(path, n, "expected 'Frame: <n> Time: <seconds>', found '" + line + "'");
  RadiateFrame r;
  const std::int64_t frame = detail::parseInt64(path, n, f, "frame number");
  if (frame < 0 || frame > 999999) throw IoError(path, n, "frame number " + f + " outside 0..999999");
  r.frame = static_cast<int>(frame);
  const std::size_t dot = t.find('.');
  const std::string whole = t.substr(0, dot);
  std::string frac = dot == std::string::npos ? "" : t.substr(dot + 1);
  for (char c : frac)
    if (c < '0' || c > '9') throw IoError(path, n, "cannot parse time '" + t + "'");
  frac = (frac + "000000").substr(0, 6);
  const std::int64_t seconds = detail::parseInt64(path, n, whole, "time");
  // Microseconds must fit in 64 bits (and a negative time is no Navtech clock).
  if (seconds < 0 || seconds > std::numeric_limits<std::int64_t>::max() / 1000000 - 1)
    throw IoError(path, n, "time '" + t + "' out of range");
  r.stamp_us = seconds * 1000000 + detail::parseInt64(path, n, frac, "time");
  if (!before.empty() && r.stamp_us <= before.back().stamp_us)
    throw IoError(
        path, n,
        std::string(r.stamp_us == before.back().stamp_us ? "duplicated frame time" : "frame times out of order") +
            " (frame " + f + ")");
  return r;
}

}  // namespace

std::vector<RadiateFrame> readRadiateFrameTimes(const std::string& path, std::vector<IoError>* skipped) {
  return detail::readIndexLines<RadiateFrame>(path, skipped,
                                              [&](std::size_t n, const std::string& line, const auto& so_far) {
                                                return parseFrameLine(path, n, line, so_far);
                                              });
}

}  // namespace radar_ndt
