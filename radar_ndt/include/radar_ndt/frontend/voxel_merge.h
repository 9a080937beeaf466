#pragma once
// Merging a thresholded scan into small square voxels: how PCL's matchers get the scanning
// front-end's points in the comparison runs (ours merges its source itself, inside the matcher).

#include <pcl/point_cloud.h>

#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// Points merged per square voxel of `size` metres (> 0, else std::invalid_argument): position,
/// time offset and covariance averaged, power the strongest. Order: first appearance of each
/// voxel. Non-finite points and points beyond any sensible extent are dropped.
void mergeVoxels(const pcl::PointCloud<PointRadar>& in, double size, pcl::PointCloud<PointRadar>& out);

}  // namespace radar_ndt
