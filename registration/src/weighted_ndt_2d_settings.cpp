#include "radar_ndt/registration/weighted_ndt_2d_settings.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "radar_ndt/registration/weighted_ndt_2d_result.h"

namespace radar_ndt {
void WeightedNDT2DSettings::validate() const {
  if (resolutions.empty())
    throw std::invalid_argument("WeightedNDT2DSettings: resolutions is empty (one grid size at least)");
  checkFields(*this, "WeightedNDT2DSettings");
}

const char* toString(WeightedNDT2DStatus status) {
  switch (status) {
    case WeightedNDT2DStatus::NotRun: return "not-run";
    case WeightedNDT2DStatus::Converged: return "converged";
    case WeightedNDT2DStatus::Stuck: return "stuck";
    case WeightedNDT2DStatus::IterationLimit: return "iteration-limit";
    case WeightedNDT2DStatus::Degenerate: return "degenerate";
  }
  return "?";
}

}  // namespace radar_ndt
