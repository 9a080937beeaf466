#pragma once
// PCD files of radar_ndt::PointRadar clouds, throwing IoError naming the file instead of returning
// -1. Reading uses RadarNDT's own checked parser; writing uses pcl::io (compiled once in the io
// library). Plain pcl::io::loadPCDFile / savePCDFile work on PointRadar too, on trusted files.

#include <string>

#include <pcl/point_cloud.h>

#include "radar_ndt/point_types.h"

namespace radar_ndt {

/// Loads a PCD file (ascii, binary or binary_compressed; any field order and numeric types) with
/// RadarNDT's own parser, which checks the header against the file size before allocating. Fields
/// of PointRadar that the file lacks keep their defaults (power 1, the rest 0); x and y are
/// required. Points with NaN or Inf coordinates are dropped and counted in `dropped_non_finite`,
/// or, when it is null, in a PCL warning naming the file. Throws IoError naming the file.
pcl::PointCloud<PointRadar> loadPointRadarPcd(const std::string& path, std::size_t* dropped_non_finite = nullptr);

/// Saves binary (default) or ASCII PCD, atomically (temporary file + rename).
void savePointRadarPcd(const std::string& path, const pcl::PointCloud<PointRadar>& cloud, bool binary = true);

}  // namespace radar_ndt
