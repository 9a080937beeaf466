#pragma once
// Scanning-radar (Navtech) polar images as the readers return them (PolarScan), and how a
// dataset's azimuth index maps to the vehicle frame (PolarConvention). The datasets' own layouts:
// oxford_scan.h (Oxford Radar RobotCar), boreas_scan.h (Boreas) and radiate_scan.h (RADIATE).
//
// The datasets store one 8-bit power value per (azimuth, range bin). Where azimuth 0 points and
// which way azimuth turns are settings (PolarConvention) with each dataset's defaults; the reader
// converts them once, so a PolarScan's azimuth angles are already in the vehicle frame of
// ARCHITECTURE.md (x forward, y left, z up; angle counter-clockwise from x seen from above).

#include <cstdint>
#include <functional>
#include <vector>

#include "radar_ndt/fields.h"

namespace radar_ndt {

/// One sweep of a scanning radar in polar form.
struct PolarScan {
  int azimuths = 0;  ///< rows of `power`
  int bins = 0;      ///< range bins per azimuth
  /// Raw power, azimuth-major (`power[a * bins + b]`), 0..255; powerAt() scales it to 0..1.
  std::vector<std::uint8_t> power;
  /// Per azimuth: angle in the vehicle frame (rad, counter-clockwise from x forward, in (−π, π]).
  std::vector<double> angle;
  /// Per azimuth: timestamp in microseconds (Oxford, Boreas: from the row; RADIATE: spread evenly
  /// over the sweep from the frame time), non-decreasing.
  std::vector<std::int64_t> stamp_us;
  /// Per azimuth: true where the sensor measured it (Oxford flag 255); false where it interpolated
  /// the row (still usable data). RADIATE has no flag: all true.
  std::vector<std::uint8_t> measured;
  /// Per azimuth: the raw encoder count (Oxford, Boreas: out of `encoder_size`); empty for RADIATE.
  std::vector<std::uint16_t> encoder;
  /// Per azimuth, for radars that alternate chirps (Boreas from 2024): 1 for an up-chirp, 0 for a
  /// down-chirp, whose ranges are shifted by a Doppler-dependent amount in opposite directions.
  /// Empty when the scan has no chirp types.
  std::vector<std::uint8_t> chirp_up;
  double range_resolution = 0.0;   ///< metres per bin
  double range_offset_bins = 0.0;  ///< range of bin b is (b + range_offset_bins) · range_resolution
  std::int64_t stamp =
      0;  ///< the scan's reference timestamp (µs): the file name (Oxford: first row; Boreas: middle row)

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
  /// The field table (radar_ndt/fields.h).
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void PolarConvention::fields(Visit&& visit) {
  using S = PolarConvention;
  visit(&S::range_resolution, Field("range_resolution", "range bin size").unit("m").positive().cli("bin-size"));
  visit(&S::range_offset_bins, Field("range_offset_bins", "bin b covers the range (b + offset) · resolution"));
  visit(&S::azimuth_zero, Field("azimuth_zero", "vehicle-frame angle of azimuth 0, CCW from x forward").unit("rad"));
  visit(&S::clockwise, Field("clockwise", "the sensor's azimuth grows clockwise seen from above"));
}

/// Moves each row a of `scan` by `shift_m(a)` metres along range (what lay at r then lies at
/// r + shift), resampled linearly between bins, zeros shifted in: the range shift of an FMCW chirp
/// (the simulator's chirp model, and its correction in frontend/chirp_correction.h). Only the first
/// `bins` bins of each row are rewritten (−1: all), for a reader that uses no more of them.
void shiftRanges(PolarScan& scan, const std::function<double(int)>& shift_m, int bins = -1);

}  // namespace radar_ndt
