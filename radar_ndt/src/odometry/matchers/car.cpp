// The car's own dead reckoning, the baselines radar odometry in a car must beat (CarFusion): no
// matching, the motion from the CAN bus's yaw-rate gyro and rear wheel speeds (wheel-gyro), or from
// the gyro's rotation and the Doppler ego-velocity's translation (doppler-gyro).
#include "builtin_matchers.h"

namespace radar_ndt {
namespace matchers {

MatcherEntry wheelGyro() {
  MatcherUses uses;
  uses.gyro = true;
  uses.wheels = true;
  uses.doppler_fusion = false;
  return {"wheel-gyro", "the car's own dead reckoning: rear wheel speeds and the gyro, no radar; automotive (CAN bus)",
          uses, MatchCalibration::WeightedNdt, [](const MatcherOptions&) { return MatcherAdapter(); }};
}

MatcherEntry dopplerGyro() {
  MatcherUses uses;
  uses.needs_doppler = true;
  uses.gyro = true;
  return {"doppler-gyro",
          "the Doppler ego-velocity's translation with the gyro's rotation, no matching; automotive (CAN bus)", uses,
          MatchCalibration::WeightedNdt, [](const MatcherOptions&) { return MatcherAdapter(); }};
}

}  // namespace matchers
}  // namespace radar_ndt
