#pragma once
// Oxford Radar RobotCar scans: `radar/<timestamp>.png` (one row per azimuth: 11 metadata bytes, then
// the range bins) and the sequence's index `radar.timestamps`. Its ground truth is read by
// oxford_ground_truth.h.

#include <cstdint>
#include <string>
#include <vector>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/polar_scan.h"

namespace radar_ndt {

/// Oxford Radar RobotCar `radar/<timestamp>.png`: one row per azimuth, 11 metadata bytes then
/// `bins` range bins. Dataset defaults: 0.0438 m bins (the dataset paper; its SDK's loader uses
/// 0.0432 m, 1.4 % smaller), bin b centred at (b + 0.5)·res (the SDK's convention), encoder 0
/// straight ahead, growing clockwise, 5600 counts a turn.
struct OxfordPolarOptions {
  PolarConvention convention{0.0438, 0.5, 0.0, true};
  int encoder_size = 5600;
  /// Range bins a row must have (the CTS350-X writes 3768); 0 accepts any width above 11.
  int expected_bins = 3768;
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void OxfordPolarOptions::fields(Visit&& visit) {
  using S = OxfordPolarOptions;
  visit(&S::convention, Field("convention", "bins and azimuths"));
  visit(&S::encoder_size, Field("encoder_size", "encoder counts a turn").atLeast(1));
  visit(&S::expected_bins, Field("expected_bins",
                                 "range bins a PNG row must have after its 11 metadata bytes (the CTS350-X's); "
                                 "0 accepts any width")
                               .atLeast(0)
                               .cli("bins"));
}

/// Reads an Oxford polar PNG (8-bit grayscale). The scan stamp is the file name's number when the
/// name is one (as in the dataset), else the first azimuth's. Throws IoError naming the file when
/// it is not a PNG, is truncated, is not 8-bit grayscale, has the wrong width, an encoder count
/// outside [0, encoder_size), or azimuth timestamps that go backwards.
PolarScan readOxfordPolarPng(const std::string& path, const OxfordPolarOptions& options = {});

/// Writes `scan` in the Oxford layout (angles back to encoder counts, the timestamps and flags of
/// each row), atomically. `compression_level` is zlib's (1 fast … 9 small).
void writeOxfordPolarPng(const std::string& path, const PolarScan& scan, const OxfordPolarOptions& options = {},
                         int compression_level = 1);

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

}  // namespace radar_ndt
