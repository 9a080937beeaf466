#define PCL_NO_PRECOMPILE
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include <pcl/console/print.h>

#include <pcl/io/pcd_io.h>

#include "pcd_header.h"
#include "radar_ndt/io/io_error.h"
#include "radar_ndt/io/pcd.h"

namespace radar_ndt {

pcl::PointCloud<PointRadar> loadPointRadarPcd(const std::string& path, std::size_t* dropped_non_finite) {
  // Our own parser, not pcl::PCDReader: PCL's reader allocates what a header claims and has
  // memory errors on malformed headers (found by fuzz/fuzz_nuscenes_pcd).
  const detail::PcdHeader h = detail::readPcdHeader(path);
  static const std::vector<std::string> kNames = {"x",      "y",      "z",       "power",       "rcs",      "cov_xx",
                                                  "cov_xy", "cov_yy", "doppler", "time_offset", "sensor_id"};
  for (const char* required : {"x", "y"})
    if (h.find(required) < 0)
      throw IoError(path, std::string("no field '") + required + "': not a point cloud with x and y");
  const std::vector<double> t = detail::readPcdColumns(path, h, kNames);
  pcl::PointCloud<PointRadar> cloud;
  cloud.reserve(h.points);
  std::size_t dropped = 0;
  // A field the file lacks keeps PointRadar's default (power 1, the rest 0).
  auto value = [](double v, float fallback) { return detail::finiteAsFloat(v) ? static_cast<float>(v) : fallback; };
  for (std::size_t i = 0; i < h.points; ++i) {
    const double* r = &t[i * kNames.size()];
    const double z = std::isnan(r[2]) && h.find("z") < 0 ? 0.0 : r[2];
    if (!detail::finiteAsFloat(r[0]) || !detail::finiteAsFloat(r[1]) || !detail::finiteAsFloat(z)) {
      ++dropped;
      continue;
    }
    PointRadar p(static_cast<float>(r[0]), static_cast<float>(r[1]), static_cast<float>(z), value(r[3], 1.f));
    p.rcs = value(r[4], 0.f);
    p.cov_xx = value(r[5], 0.f);
    p.cov_xy = value(r[6], 0.f);
    p.cov_yy = value(r[7], 0.f);
    p.doppler = value(r[8], 0.f);
    p.time_offset = value(r[9], 0.f);
    p.sensor_id = std::isfinite(r[10]) && r[10] >= 0 && r[10] <= 65535 ? static_cast<std::uint16_t>(r[10]) : 0;
    cloud.push_back(p);
  }
  // An organised file keeps its layout only when every point was kept.
  if (dropped == 0 && h.height > 1) {
    cloud.width = static_cast<std::uint32_t>(h.width);
    cloud.height = static_cast<std::uint32_t>(h.height);
  }
  cloud.is_dense = true;
  if (dropped_non_finite) {
    *dropped_non_finite = dropped;
  } else if (dropped > 0) {
    pcl::console::print_warn("%s: dropped %zu points with NaN or Inf coordinates\n", path.c_str(), dropped);
  }
  return cloud;
}

void savePointRadarPcd(const std::string& path, const pcl::PointCloud<PointRadar>& cloud, bool binary) {
  const std::string tmp = path + ".tmp." + std::to_string(static_cast<long>(::getpid()));
  pcl::PCDWriter writer;
  if (writer.write(tmp, cloud, binary) != 0) {
    std::remove(tmp.c_str());
    throw IoError(path, "cannot write PCD file");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw IoError(path, "cannot rename the temporary file into place");
  }
}

}  // namespace radar_ndt
