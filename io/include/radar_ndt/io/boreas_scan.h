#pragma once
// Boreas scans (University of Toronto; Navtech radars): `<sequence>/radar/<stamp>.png`, read as
// the dataset's SDK reads them (pyboreas/utils/radar.py `load_radar`; docs/data_formats.md gives
// each convention with its source). The sequence's ground truth is boreas_ground_truth.h.
//
// A Boreas PNG has Oxford's row layout: per azimuth an 8-byte little-endian timestamp (µs), a
// 2-byte encoder count out of 5600, one flag byte, then the range bins. What differs from Oxford:
//  - the file name is the timestamp of row 199 (floor(M / 2) − 1 of M = 400 rows), the middle of
//    the sweep, not its first row;
//  - the range bin depends on the sensor, which the SDK decides by the file name's time: 0.0596 m
//    before 2021-09-21 (`radar_resolution_upgrade_time`), 0.04381 m after;
//  - the SDK zeroes the bins under 2.5 m;
//  - in scans with Doppler chirps (2024 on) the flag byte is the azimuth's chirp type (255 up,
//    0 down, alternating), not a validity flag.

#include <cstdint>
#include <string>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/polar_scan.h"

namespace radar_ndt {

/// The SDK's sensor-upgrade time (Unix s, 2021-09-21 00:00 UTC) and the bins on either side.
constexpr double kBoreasResolutionUpgradeTime = 1632182400.0;
constexpr double kBoreasBinBeforeUpgrade = 0.0596;
constexpr double kBoreasBinAfterUpgrade = 0.04381;

/// A time token in seconds as the SDK's `get_time_from_filename` reads it: 16 digits are
/// microseconds; other lengths over 10 digits have their last (length − 10) digits after the
/// decimal point (19 digits: nanoseconds); 10 or fewer are seconds. Returns false when the token
/// is not all digits (or is empty or longer than 19 digits).
bool boreasTimeSeconds(const std::string& token, double* seconds);
/// The same token in whole microseconds (nanoseconds rounded down, as the dataset names a scan).
bool boreasTimeMicros(const std::string& token, std::int64_t* micros);

/// The range bin (m) of a Boreas scan taken at `time_s`, as the SDK decides it.
double boreasRangeResolution(double time_s);

/// How the flag byte is read.
enum class BoreasFlag {
  Auto,       ///< chirp types when the byte alternates 0/255 row by row, else validity flags
  Validity,   ///< 255: measured azimuth; else interpolated (Boreas before the chirp upgrade)
  ChirpType,  ///< 255: up-chirp; 0: down-chirp
};
template <>
struct EnumNames<BoreasFlag> {
  static constexpr const char* what = "Boreas flag byte";
  static constexpr EnumName<BoreasFlag> names[] = {
      {BoreasFlag::Auto, "auto", "chirp types when the byte alternates 0/255 row by row, else validity"},
      {BoreasFlag::Validity, "validity", "255: measured azimuth"},
      {BoreasFlag::ChirpType, "chirp-type", "255: up-chirp, 0: down-chirp"}};
};

struct BoreasPolarOptions {
  /// m per bin; 0: by the file name's time as the SDK decides (boreasRangeResolution).
  double range_resolution = 0.0;
  /// Bin b at (b + 0.5) · resolution, as the SDK's `radar_polar_to_cartesian` samples it (the
  /// dataset reference's −0.31 m Navtech offset is not applied by the SDK either).
  double range_offset_bins = 0.5;
  /// m: bins nearer than this are zeroed, as the SDK's loader does (round(2.5 / resolution)).
  double zero_below = 2.5;
  int encoder_size = 5600;
  BoreasFlag flag = BoreasFlag::Auto;
  /// Range bins a row must have (0: any). The two sensors write 3360 and 6848.
  int expected_bins = 0;
  /// Throws std::invalid_argument naming the setting out of range.
  void validate() const;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void BoreasPolarOptions::fields(Visit&& visit) {
  using S = BoreasPolarOptions;
  visit(&S::range_resolution, Field("range_resolution",
                                    "range bin size; 0: by the scan's date as the SDK decides (0.0596 m before "
                                    "2021-09-21, 0.04381 m after)")
                                  .unit("m")
                                  .atLeast(0)
                                  .cli("bin-size"));
  visit(&S::range_offset_bins, Field("range_offset_bins", "bin b at (b + offset) · resolution, as the SDK samples"));
  visit(&S::zero_below, Field("zero_below", "bins nearer than this zeroed, as the SDK's loader").unit("m").atLeast(0));
  visit(&S::encoder_size, Field("encoder_size", "encoder counts a turn").atLeast(1));
  visit(&S::flag, Field("flag", "what each row's flag byte is"));
  visit(&S::expected_bins,
        Field("expected_bins", "range bins a row must have (the sensors write 3360 and 6848); 0: any")
            .atLeast(0)
            .cli("bins"));
}

/// Reads a Boreas polar PNG (8-bit grayscale). Azimuth angles go to the vehicle frame (the encoder
/// turns clockwise seen from above from x forward; see polar_scan.h). The scan stamp is the file
/// name's time (µs, the sweep's middle row) when the name is a number, else row 199's timestamp.
/// Throws IoError naming the file when it is not a PNG, is truncated, is not 8-bit grayscale, has
/// the wrong width, an encoder count outside [0, encoder_size), or timestamps that go backwards.
PolarScan readBoreasPolarPng(const std::string& path, const BoreasPolarOptions& options = {});

/// Writes `scan` in the Boreas layout, atomically: the row timestamps, encoder counts and, per
/// azimuth, the chirp type (when `scan.chirp_up` is filled) or the validity flag.
void writeBoreasPolarPng(const std::string& path, const PolarScan& scan, int encoder_size = 5600,
                         int compression_level = 1);

}  // namespace radar_ndt
