// pw-ndt, the paper's weighted probabilistic NDT (WeightedNDT2D), and rapp-ndt, the same matcher
// with Rapp et al.'s Doppler-agreement weights (grid-based, as the paper compares it).
#include "builtin_matchers.h"

namespace radar_ndt {
namespace matchers {

namespace {
/// WeightedNDT2D with the options' settings; its grid and power shift are the adapter's to set
/// (the nominal ones here, an attempt's later).
MatcherAdapter makeWeightedNdt(const MatcherOptions& options) {
  auto r = pcl::make_shared<WeightedNDT2D<PointRadar, PointRadar>>();
  WeightedNDT2DSettings s = options.weighted_ndt;
  s.shift_source_weights = options.shift_source_weights;
  r->setSettings(s);
  r->setMaximumIterations(options.weighted_ndt_max_iterations);
  return MatcherAdapter(r, options.nominal());
}
}  // namespace

MatcherEntry pwNdt() {
  MatcherUses uses;
  uses.power_weights = true;
  uses.sweep_times = true;
  uses.merges_source = true;
  return {"pw-ndt", "the paper's weighted probabilistic NDT", uses, MatchCalibration::WeightedNdt, &makeWeightedNdt};
}

MatcherEntry rappNdt() {
  MatcherUses uses;
  uses.power_weights = true;
  uses.doppler_weights = true;
  uses.needs_doppler = true;
  uses.merges_source = true;
  return {"rapp-ndt", "Doppler-weighted grid NDT (Rapp et al. 2017), automotive", uses, MatchCalibration::Rapp,
          &makeWeightedNdt};
}

}  // namespace matchers
}  // namespace radar_ndt
