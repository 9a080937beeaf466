#include "radar_ndt/evaluation/point_map.h"

#include <cmath>
#include <stdexcept>

#include "radar_ndt/io/pcd.h"

namespace radar_ndt {

PointMap::PointMap(double voxel) : voxel_(voxel) {
  if (!(voxel >= 0.0) || !std::isfinite(voxel)) throw std::invalid_argument("PointMap: voxel must be >= 0 (m)");
}

void PointMap::add(const pcl::PointCloud<PointRadar>& cloud, const Pose2& pose) {
  const double c = std::cos(pose.z()), s = std::sin(pose.z());
  for (const PointRadar& p : cloud) {
    PointRadar w = p;
    const double x = pose.x() + c * p.x - s * p.y;
    const double y = pose.y() + s * p.x + c * p.y;
    w.x = static_cast<float>(x);
    w.y = static_cast<float>(y);
    if (voxel_ > 0.0) {
      // 21 bits a coordinate (±1e6 voxels): a key for any map a run makes.
      const auto cell = [&](double v) {
        return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / voxel_)) + (1 << 20)) & 0x1FFFFF;
      };
      const std::uint64_t key = (cell(x) << 42) | (cell(y) << 21) | cell(p.z);
      if (!occupied_.insert(key).second) continue;
    }
    cloud_.push_back(w);
  }
}

void PointMap::write(const std::string& path) const {
  savePointRadarPcd(path, cloud_, true);
}

}  // namespace radar_ndt
