#pragma once
// RADIATE scans: `Navtech_Polar/NNNNNN.png` (azimuth columns, range rows, no metadata) and the
// sequence's frame times `Navtech_Polar.txt`.

#include <cstdint>
#include <string>
#include <vector>

#include "radar_ndt/fields.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/polar_scan.h"

namespace radar_ndt {

/// RADIATE `Navtech_Polar/NNNNNN.png`: 400 azimuth columns × 576 range rows, no metadata.
/// Dataset defaults: 0.173611 m bins, bin 0 at 0 m (the RADIATE SDK), column 0 straight ahead,
/// azimuth growing clockwise as on every Navtech (a setting: the dataset does not say).
struct RadiatePolarOptions {
  PolarConvention convention{0.173611, 0.0, 0.0, true};
  int expected_azimuths = 400;  ///< 0 accepts any
  double sweep_period = 0.25;   ///< s; per-azimuth timestamps are spread over it from the frame time
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void RadiatePolarOptions::fields(Visit&& visit) {
  using S = RadiatePolarOptions;
  visit(&S::convention, Field("convention", "bins and azimuths"));
  visit(&S::expected_azimuths, Field("expected_azimuths", "azimuths a scan must have; 0 accepts any").atLeast(0));
  visit(&S::sweep_period,
        Field("sweep_period", "the azimuths' times spread over this from the frame time").unit("s").positive());
}

/// Reads a RADIATE polar PNG. `frame_time_us` is the frame's time (Navtech_Polar.txt); azimuth
/// timestamps are spread over `sweep_period` from it.
PolarScan readRadiatePolarPng(const std::string& path, std::int64_t frame_time_us = 0,
                              const RadiatePolarOptions& options = {});

/// RADIATE `Navtech_Polar.txt`: `Frame: 000001 Time: 1574859771.744660272` a line.
struct RadiateFrame {
  int frame = 0;
  std::int64_t stamp_us = 0;
};
/// Frame numbers 0..999999 (the file names), strictly increasing times; `skipped` as for
/// readOxfordTimestamps.
std::vector<RadiateFrame> readRadiateFrameTimes(const std::string& path, std::vector<IoError>* skipped = nullptr);

}  // namespace radar_ndt
