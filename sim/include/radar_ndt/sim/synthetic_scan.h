#pragma once
// Synthetic 2D radar-like scan pairs with a known transform, for tests and benchmarks: a seeded
// world of walls, building corners, poles and arcs, sampled independently from two poses (so the
// two scans share structure, not points), with optional range-independent position noise and
// low-power clutter. Not the realistic radar simulator (radar_sim): no beams, no occlusion.

#include <cstdint>

#include <pcl/point_cloud.h>

#include "radar_ndt/point_types.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {

struct SyntheticScanOptions {
  std::size_t points = 10000;      ///< points per scan (structure + clutter)
  double extent = 60.0;            ///< structures lie within this distance of the origin (m)
  double noise_std = 0.0;          ///< isotropic position noise (m), also written as the point covariance
  double clutter_fraction = 0.0;   ///< fraction of points that are uniform random clutter
  float clutter_power_max = 0.3f;  ///< clutter power in [0.02, this]; structure power in [0.5, 1]
  double max_translation = 2.0;    ///< |t| of the true transform up to this (m), uniform direction
  double max_rotation_deg = 3.0;   ///< |yaw| up to this
  std::uint32_t seed = 1;
  /// Throws std::invalid_argument naming the first setting out of range.
  void validate() const;
};

struct SyntheticScanPair {
  pcl::PointCloud<PointRadar> source;
  pcl::PointCloud<PointRadar> target;
  /// The pose of the source frame in the target frame: target ≈ T · source (what align() returns).
  Pose2 source_in_target = Pose2::Zero();
};

SyntheticScanPair makeSyntheticScanPair(const SyntheticScanOptions& options);

}  // namespace radar_ndt
