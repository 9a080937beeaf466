#pragma once
// The registry of 3D matchers, for 4D radar scans (PointRadar4D): as matcher_registry.h for the
// planar pipelines, a name maps to a factory, here of a pcl::Registration on SE(3), so that the
// 6-DoF pipeline's --method and radar_ndt3d_bench pick a matcher by name and a user adds one with
// registerMatcher3D. Built-in: pw-ndt-3d (WeightedNDT3D), pcl-ndt-3d, pcl-gicp, one file each in
// radar_ndt/src/odometry/matchers/ (PCL's templates for PointRadar4D compiled there, once).

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <pcl/registration/registration.h>

#include "radar_ndt/fields.h"
#include "radar_ndt/point_types.h"
#include "radar_ndt/registration/weighted_ndt_3d.h"

namespace radar_ndt {

using Registration3D = pcl::Registration<PointRadar4D, PointRadar4D, float>;

/// Every 3D matcher's settings, each in one place. PCL's are those its matchers are compared with
/// in docs/results/matcher_3d.md (NDT: the best of a sweep; GICP: PCL's defaults with a 3 m
/// correspondence distance).
struct Matcher3DOptions {
  WeightedNDT3DSettings ndt;  ///< pw-ndt-3d
  double pcl_ndt_resolution = 2.0, pcl_ndt_step = 0.5, pcl_ndt_epsilon = 0.01;
  int pcl_ndt_iterations = 35;
  double gicp_max_correspondence = 3.0;
  int gicp_iterations = 50;
  void validate() const;
  template <typename Visit>
  static void fields(Visit&& visit);
};

template <typename Visit>
void Matcher3DOptions::fields(Visit&& visit) {
  using S = Matcher3DOptions;
  visit(&S::pcl_ndt_resolution, Field("pcl_ndt_resolution", "pcl-ndt-3d: its cells' size").unit("m").positive());
  visit(&S::pcl_ndt_step, Field("pcl_ndt_step", "pcl-ndt-3d: its line search's largest step").unit("m").positive());
  visit(&S::pcl_ndt_epsilon,
        Field("pcl_ndt_epsilon", "pcl-ndt-3d: the transformation epsilon that stops it").positive());
  visit(&S::pcl_ndt_iterations, Field("pcl_ndt_iterations", "pcl-ndt-3d: iterations at most").atLeast(1));
  visit(&S::gicp_max_correspondence,
        Field("gicp_max_correspondence", "pcl-gicp: the farthest correspondence").unit("m").positive());
  visit(&S::gicp_iterations, Field("gicp_iterations", "pcl-gicp: iterations at most").atLeast(1));
}

struct Matcher3DEntry {
  std::string name;                ///< as --method spells it
  std::string help;                ///< a phrase: what the method is
  bool point_covariances = false;  ///< uses each point's own covariance (cov_xx … of PointRadar4D)
  /// A new matcher with `options`' settings.
  std::function<std::shared_ptr<Registration3D>(const Matcher3DOptions&)> make;
  /// The iterations of `r`'s last align (r made by `make`).
  std::function<int(const Registration3D& r)> iterations;
};

/// Adds `entry`; std::invalid_argument for an empty name, factory or iteration count, or a name
/// already taken.
void registerMatcher3D(Matcher3DEntry entry);
/// The entry named `name`; std::invalid_argument naming the registered ones otherwise.
const Matcher3DEntry& findMatcher3D(const std::string& name);
/// The registered names, built-in ones first, in the order they were registered.
std::vector<std::string> matcher3DNames();

}  // namespace radar_ndt
