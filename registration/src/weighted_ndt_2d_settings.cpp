#include "radar_ndt/registration/weighted_ndt_2d_settings.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace radar_ndt {

void WeightedNDT2DSettings::validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("WeightedNDT2DSettings: " + what); };
  if (resolutions.empty()) fail("resolutions is empty (one grid size at least)");
  for (const float g : resolutions)
    if (!(g > 0.0f) || !std::isfinite(g)) fail("resolutions must be positive and finite, got " + std::to_string(g));
  if (!std::isfinite(power_shift)) fail("power_shift must be finite");
  if (!(eigenvalue_ratio > 0.0 && eigenvalue_ratio <= 1.0))
    fail("eigenvalue_ratio must be in (0, 1], got " + std::to_string(eigenvalue_ratio));
  if (min_points_per_cell < 1) fail("min_points_per_cell must be >= 1, got " + std::to_string(min_points_per_cell));
  if (!(source_voxel_size >= 0.0) || !std::isfinite(source_voxel_size))
    fail("source_voxel_size must be >= 0 and finite, got " + std::to_string(source_voxel_size));
  if (!std::isfinite(max_step_translation)) fail("max_step_translation must be finite (<= 0: half the grid size)");
  if (!(max_step_rotation > 0.0) || !std::isfinite(max_step_rotation))
    fail("max_step_rotation must be > 0 and finite, got " + std::to_string(max_step_rotation));
}

}  // namespace radar_ndt
