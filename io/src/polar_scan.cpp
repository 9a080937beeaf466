#include "radar_ndt/io/polar_scan.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace {

constexpr double kTwoPi = 2.0 * kPi;

double wrapPi(double a) {
  a = std::fmod(a, kTwoPi);
  if (a > kPi) a -= kTwoPi;
  if (a <= -kPi) a += kTwoPi;
  return a;
}

}  // namespace

double PolarConvention::toVehicleAngle(double sensor_azimuth) const {
  return wrapPi(azimuth_zero + (clockwise ? -sensor_azimuth : sensor_azimuth));
}

double PolarConvention::toSensorAzimuth(double vehicle_angle) const {
  double a = clockwise ? azimuth_zero - vehicle_angle : vehicle_angle - azimuth_zero;
  a = std::fmod(a, kTwoPi);
  if (a < 0) a += kTwoPi;
  return a;
}

void shiftRanges(PolarScan& scan, const std::function<double(int)>& shift_m, int bins) {
  const int written = bins < 0 ? scan.bins : std::min(bins, scan.bins);
  std::vector<std::uint8_t> row(static_cast<std::size_t>(scan.bins) + 2, 0);  // a zero either side
  for (int a = 0; a < scan.azimuths; ++a) {
    const double shift_bins = shift_m(a) / scan.range_resolution;
    if (shift_bins == 0.0) continue;
    std::uint8_t* out = scan.row(a);
    std::copy(out, out + scan.bins, row.begin() + 1);
    const int whole = static_cast<int>(std::floor(shift_bins));
    // What lay at bin b − shift now shows at b: between bins i = b − whole − 1 and i + 1, with
    // weights f and 1 − f (f = the shift's fraction, in 256ths).
    const int f = static_cast<int>(std::lround((shift_bins - whole) * 256.0));
    for (int b = 0; b < written; ++b) {
      const int i = b - whole - 1;
      const int lo = i >= -1 && i <= scan.bins ? row[static_cast<std::size_t>(i + 1)] : 0;
      const int hi = i + 1 >= -1 && i + 1 <= scan.bins ? row[static_cast<std::size_t>(i + 2)] : 0;
      out[b] = static_cast<std::uint8_t>((f * lo + (256 - f) * hi + 128) >> 8);
    }
  }
}

}  // namespace radar_ndt
