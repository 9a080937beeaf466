#include "radar_ndt/registration/weighted_ndt_2d_settings.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "radar_ndt/registration/weighted_ndt_2d_result.h"

namespace radar_ndt {
namespace {

[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument("WeightedNDT2DSettings: " + what);
}

void requireInOpenUnit(double v, const char* name) {
  if (!(v > 0.0 && v < 1.0)) fail(std::string(name) + " must be in (0, 1), got " + std::to_string(v));
}

void requireNonNegative(double v, const char* name) {
  if (!(v >= 0.0) || !std::isfinite(v)) fail(std::string(name) + " must be >= 0 and finite, got " + std::to_string(v));
}

void validateSolve(const WeightedNDT2DSettings& s) {
  if (s.coarse_subsample < 1) fail("coarse_subsample must be >= 1 (1: no coarse phase)");
  if (s.coarse_min_points < 0) fail("coarse_min_points must be >= 0");
  if (!(s.coarse_transformation_epsilon > 0.0) || !std::isfinite(s.coarse_transformation_epsilon))
    fail("coarse_transformation_epsilon must be > 0 and finite (m²)");
  if (!(s.coarse_rotation_epsilon > 0.0) || !std::isfinite(s.coarse_rotation_epsilon))
    fail("coarse_rotation_epsilon must be > 0 and finite (rad)");
  requireNonNegative(s.stationary_translation_ratio, "stationary_translation_ratio");
  requireNonNegative(s.stationary_rotation, "stationary_rotation");
  requireInOpenUnit(s.armijo, "armijo");
  if (s.max_halvings < 1) fail("max_halvings must be >= 1 (the full step is the first trial)");
  requireInOpenUnit(s.eigenvalue_floor, "eigenvalue_floor");
  requireNonNegative(s.negligible_decrease, "negligible_decrease");
  if (s.min_matched_points < 1) fail("min_matched_points must be >= 1");
  if (!(s.min_information_ratio >= 0.0 && s.min_information_ratio < 1.0))
    fail("min_information_ratio must be in [0, 1)");
}

}  // namespace

void WeightedNDT2DSettings::validate() const {
  if (resolutions.empty()) fail("resolutions is empty (one grid size at least)");
  for (const float g : resolutions)
    if (!(g > 0.0f) || !std::isfinite(g)) fail("resolutions must be positive and finite, got " + std::to_string(g));
  if (!std::isfinite(power_shift)) fail("power_shift must be finite");
  if (!(eigenvalue_ratio > 0.0 && eigenvalue_ratio <= 1.0))
    fail("eigenvalue_ratio must be in (0, 1], got " + std::to_string(eigenvalue_ratio));
  if (min_points_per_cell < 1) fail("min_points_per_cell must be >= 1, got " + std::to_string(min_points_per_cell));
  requireNonNegative(source_voxel_size, "source_voxel_size");
  if (!std::isfinite(max_step_translation)) fail("max_step_translation must be finite (<= 0: half the grid size)");
  if (!(max_step_rotation > 0.0) || !std::isfinite(max_step_rotation))
    fail("max_step_rotation must be > 0 and finite, got " + std::to_string(max_step_rotation));
  validateSolve(*this);
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
