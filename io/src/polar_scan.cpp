#include "radar_ndt/io/polar_scan.h"

#include <cmath>

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

}  // namespace radar_ndt
