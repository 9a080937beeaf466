// doppler: no matching; the odometry integrates Kellner's Doppler ego-velocity (the automotive
// pipeline's prior, the baseline every matcher stands beside).
#include "builtin_matchers.h"

namespace radar_ndt {
namespace matchers {

MatcherEntry doppler() {
  MatcherUses uses;
  uses.needs_doppler = true;
  return {"doppler", "Kellner's ego-velocity integrated, no matching; automotive", uses, MatchCalibration::WeightedNdt,
          [](const MatcherOptions&) { return MatcherAdapter(); }};
}

}  // namespace matchers
}  // namespace radar_ndt
