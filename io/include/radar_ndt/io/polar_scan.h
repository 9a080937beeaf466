#pragma once
// Scanning-radar (Navtech) polar images: the Oxford Radar RobotCar and RADIATE layouts, and the
// Oxford sequence files around them (radar.timestamps, gt/radar_odometry.csv).
//
// Both datasets store one 8-bit power value per (azimuth, range bin). Where azimuth 0 points and
// which way azimuth turns are settings (PolarConvention) with each dataset's defaults; the reader
// converts them once, so a PolarScan's azimuth angles are already in the vehicle frame of
// ARCHITECTURE.md (x forward, y left, z up; angle counter-clockwise from x seen from above).

#include <cstdint>
#include <string>
#include <vector>

#include "radar_ndt/io/io_error.h"

namespace radar_ndt {

/// One sweep of a scanning radar in polar form.
struct PolarScan {
  int azimuths = 0;  ///< rows of `power`
  int bins = 0;      ///< range bins per azimuth
  /// Raw power, azimuth-major (`power[a * bins + b]`), 0..255; powerAt() scales it to 0..1.
  std::vector<std::uint8_t> power;
  /// Per azimuth: angle in the vehicle frame (rad, counter-clockwise from x forward, in (−π, π]).
  std::vector<double> angle;
  /// Per azimuth: timestamp in microseconds (Oxford: from the row; RADIATE: spread evenly over the
  /// sweep from the frame time), non-decreasing.
  std::vector<std::int64_t> stamp_us;
  /// Per azimuth: true where the sensor measured it (Oxford flag 255); false where it interpolated
  /// the row (still usable data). RADIATE has no flag: all true.
  std::vector<std::uint8_t> measured;
  /// Per azimuth: the raw encoder count (Oxford, out of `encoder_size`); empty for RADIATE.
  std::vector<std::uint16_t> encoder;
  double range_resolution = 0.0;   ///< metres per bin
  double range_offset_bins = 0.0;  ///< range of bin b is (b + range_offset_bins) · range_resolution
  std::int64_t stamp = 0;          ///< the scan's reference timestamp (µs): Oxford: the file name

  float powerAt(int a, int b) const {
    return static_cast<float>(power[static_cast<std::size_t>(a) * bins + b]) / 255.0f;
  }
  const std::uint8_t* row(int a) const { return power.data() + static_cast<std::size_t>(a) * bins; }
  std::uint8_t* row(int a) { return power.data() + static_cast<std::size_t>(a) * bins; }
  double rangeOf(double bin) const { return (bin + range_offset_bins) * range_resolution; }
  double maxRange() const { return rangeOf(bins - 1); }
};

/// How a dataset's azimuth index maps to the vehicle frame, and its range bins.
struct PolarConvention {
  double range_resolution = 0.0438;  ///< m per bin
  double range_offset_bins = 0.5;    ///< bin b covers the range (b + offset) · resolution
  /// Vehicle-frame angle (rad, CCW from x forward) of azimuth 0.
  double azimuth_zero = 0.0;
  /// true: the sensor's azimuth grows clockwise seen from above (Oxford, RADIATE's Navtech).
  bool clockwise = true;

  double toVehicleAngle(double sensor_azimuth) const;
  double toSensorAzimuth(double vehicle_angle) const;  ///< in [0, 2π)
};

/// Oxford Radar RobotCar `radar/<timestamp>.png`: one row per azimuth, 11 metadata bytes then
/// `bins` range bins. Dataset defaults: 0.0438 m bins (the dataset paper; its SDK's loader uses
/// 0.0432 m, 1.4 % smaller), bin b centred at (b + 0.5)·res (the SDK's convention), encoder 0
/// straight ahead, growing clockwise, 5600 counts a turn.
struct OxfordPolarOptions {
  PolarConvention convention{0.0438, 0.5, 0.0, true};
  int encoder_size = 5600;
  /// Range bins a row must have (the CTS350-X writes 3768); 0 accepts any width above 11.
  int expected_bins = 3768;
};

/// RADIATE `Navtech_Polar/NNNNNN.png`: 400 azimuth columns × 576 range rows, no metadata.
/// Dataset defaults: 0.173611 m bins, bin 0 at 0 m (the RADIATE SDK), column 0 straight ahead,
/// azimuth growing clockwise as on every Navtech (a setting: the dataset does not say).
struct RadiatePolarOptions {
  PolarConvention convention{0.173611, 0.0, 0.0, true};
  int expected_azimuths = 400;  ///< 0 accepts any
  double sweep_period = 0.25;   ///< s; per-azimuth timestamps are spread over it from the frame time
};

/// Reads an Oxford polar PNG (8-bit grayscale). The scan stamp is the file name's number when the
/// name is one (as in the dataset), else the first azimuth's. Throws IoError naming the file when
/// it is not a PNG, is truncated, is not 8-bit grayscale, has the wrong width, an encoder count
/// outside [0, encoder_size), or azimuth timestamps that go backwards.
PolarScan readOxfordPolarPng(const std::string& path, const OxfordPolarOptions& options = {});

/// Writes `scan` in the Oxford layout (angles back to encoder counts, the timestamps and flags of
/// each row), atomically. `compression_level` is zlib's (1 fast … 9 small).
void writeOxfordPolarPng(const std::string& path, const PolarScan& scan, const OxfordPolarOptions& options = {},
                         int compression_level = 1);

/// Reads a RADIATE polar PNG. `frame_time_us` is the frame's time (Navtech_Polar.txt); azimuth
/// timestamps are spread over `sweep_period` from it.
PolarScan readRadiatePolarPng(const std::string& path, std::int64_t frame_time_us = 0,
                              const RadiatePolarOptions& options = {});

/// Decodes an 8-bit grayscale PNG into row-major pixels, the samples exactly as stored: gamma and
/// colour-space chunks are ignored (a scan is data, not a picture), alpha is dropped, interlacing
/// is undone, and a file stored as RGB, RGBA or through a palette is taken when every pixel is grey
/// (as tools that write every image in colour leave it). Real colour and other sample depths than 8
/// bits are an IoError naming the file.
struct GrayImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
};
GrayImage readGrayPng(const std::string& path);
/// Writes an 8-bit grayscale (channels 1) or RGB (channels 3) PNG atomically.
void writePng(const std::string& path, int width, int height, int channels, const std::uint8_t* pixels,
              int compression_level = 6);

/// One line of an Oxford `radar.timestamps`: `<timestamp µs> <valid>`.
struct OxfordStamp {
  std::int64_t stamp = 0;
  bool valid = true;
};
/// Strictly increasing timestamps required; throws IoError with the line number otherwise. With
/// `skipped`, a bad line (unparsable, duplicated or out-of-order timestamp) is left out and its
/// error appended there instead, so a sequence with a few bad index lines can still be run.
std::vector<OxfordStamp> readOxfordTimestamps(const std::string& path, std::vector<IoError>* skipped = nullptr);
void writeOxfordTimestamps(const std::string& path, const std::vector<OxfordStamp>& stamps);

/// One row of Oxford `gt/radar_odometry.csv`: the motion from the destination scan (the earlier)
/// to the source scan (the later), i.e. the source scan's pose in the destination scan's frame,
/// x y z roll pitch yaw in Oxford's sensor axes (x forward, y right, z down).
struct OxfordRelativePose {
  std::int64_t source = 0;       ///< source_timestamp (later scan)
  std::int64_t destination = 0;  ///< destination_timestamp (earlier scan)
  double x = 0, y = 0, z = 0, roll = 0, pitch = 0, yaw = 0;
  std::int64_t source_radar = 0;
  std::int64_t destination_radar = 0;
};
/// Reads the CSV by its header's column names (the dataset's order:
/// source_timestamp,destination_timestamp,x,y,z,roll,pitch,yaw,source_radar_timestamp,
/// destination_radar_timestamp; the last two optional). Rows must chain in time.
std::vector<OxfordRelativePose> readOxfordRadarOdometry(const std::string& path);
void writeOxfordRadarOdometry(const std::string& path, const std::vector<OxfordRelativePose>& rows);

/// RADIATE `Navtech_Polar.txt`: `Frame: 000001 Time: 1574859771.744660272` a line.
struct RadiateFrame {
  int frame = 0;
  std::int64_t stamp_us = 0;
};
/// Frame numbers 0..999999 (the file names), strictly increasing times; `skipped` as for
/// readOxfordTimestamps.
std::vector<RadiateFrame> readRadiateFrameTimes(const std::string& path, std::vector<IoError>* skipped = nullptr);

}  // namespace radar_ndt
