#pragma once
// The scan matchers the odometry can run, as pcl::Registration<PointRadar, PointRadar> objects:
// ours, and PCL's NDT and ICP with the settings README documents. PCL's templates for PointRadar
// are compiled once, in src/matchers.cpp.

#include <string>
#include <vector>

#include <pcl/registration/registration.h>

#include "radar_ndt/point_types.h"

namespace radar_ndt {

using RadarRegistration = pcl::Registration<PointRadar, PointRadar, float>;

enum class Method {
  PwNdt,    ///< WeightedNDT2D (the paper's weighted probabilistic NDT), one point per cell minimum
  PclNdt,   ///< pcl::NormalDistributionsTransform
  PclIcp,   ///< pcl::IterativeClosestPoint
  Doppler,  ///< no matching: Kellner's ego-velocity integration
  RappNdt,  ///< grid NDT with Doppler-agreement weights (Rapp et al. 2017, grid-based as in the paper)
};

/// "pw-ndt", "pcl-ndt", "pcl-icp", "doppler", "rapp-ndt"; throws std::invalid_argument otherwise.
Method parseMethod(const std::string& name);
const char* toString(Method method);

/// A new matcher for `method` at grid size `grid` (NDT cell size; ICP: max correspondence
/// distance). nullptr for Method::Doppler.
RadarRegistration::Ptr makeMatcher(Method method, double grid);

/// The settings README documents for pcl::NormalDistributionsTransform wherever it is compared
/// with ours (any point type): resolution = grid, step 0.5, ε 1e-4, at most 50 iterations.
template <typename PclNdt>
void applyPclNdtSettings(PclNdt& ndt, double grid) {
  ndt.setResolution(static_cast<float>(grid));
  ndt.setStepSize(0.5);
  ndt.setTransformationEpsilon(1e-4);
  ndt.setMaximumIterations(50);
}

/// Sets the grid size of a matcher made by makeMatcher (used by the failure retries).
void setMatcherGrid(RadarRegistration& matcher, double grid);

/// How well the last align() fits, larger is better, comparable between aligns of the same
/// source and target: ours: the NDT score; PCL's NDT: its transformation probability; ICP: minus
/// its fitness score (mean squared nearest-neighbour distance).
double matchScore(RadarRegistration& matcher);

/// Ours only: the last align()'s NDT score per source point, comparable between scans of one
/// sequence (a scan that fits its target nowhere, e.g. all noise, scores a fraction of the usual).
/// NaN for other matchers.
double matchFitPerPoint(RadarRegistration& matcher);

/// Sets the power shift s of eq. (1)-(2) when the matcher is ours, in the cells and, when
/// shift_source (the paper), in the matching weights too; false (nothing changed) for matchers
/// without power weights (PCL's NDT and ICP).
bool setMatcherPowerShift(RadarRegistration& matcher, float shift, bool shift_source = true);

}  // namespace radar_ndt
