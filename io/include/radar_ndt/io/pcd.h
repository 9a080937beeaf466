#pragma once
// PCD files of radar_ndt::PointRadar clouds. Thin wrappers over pcl::io that throw IoError naming
// the file instead of returning -1, compiled once in the io library (custom point types make PCL's
// PCD templates slow to compile). Plain pcl::io::loadPCDFile / savePCDFile work on PointRadar too.

#include <string>

#include <pcl/point_cloud.h>

#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// Loads a PCD file; fields of PointRadar that the file lacks keep their defaults (power 1, the rest 0).
pcl::PointCloud<PointRadar> loadPointRadarPcd(const std::string& path);

/// Saves binary (default) or ASCII PCD, atomically (temporary file + rename).
void savePointRadarPcd(const std::string& path, const pcl::PointCloud<PointRadar>& cloud, bool binary = true);

}  // namespace radar_ndt
