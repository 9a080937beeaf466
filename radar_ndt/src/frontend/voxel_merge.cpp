#include "radar_ndt/frontend/voxel_merge.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace radar_ndt {

void mergeVoxels(const pcl::PointCloud<PointRadar>& in, double size, pcl::PointCloud<PointRadar>& out) {
  if (!(size > 0)) throw std::invalid_argument("mergeVoxels: voxel size must be > 0");
  out.clear();
  out.header = in.header;
  std::unordered_map<std::uint64_t, std::int32_t> index;  // voxel key → index into `out`
  index.reserve(in.size() / 2 + 16);
  std::vector<int> count;
  const double inv = 1.0 / size;
  for (const auto& p : in) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
    const double u = std::floor(p.x * inv), v = std::floor(p.y * inv);
    if (std::abs(u) > 1e9 || std::abs(v) > 1e9) continue;
    const std::uint64_t key =
        (static_cast<std::uint64_t>(static_cast<std::uint32_t>(static_cast<std::int32_t>(u))) << 32) |
        static_cast<std::uint32_t>(static_cast<std::int32_t>(v));
    const auto [it, inserted] = index.emplace(key, static_cast<std::int32_t>(out.size()));
    const std::int32_t i = it->second;
    if (inserted) {
      out.push_back(p);
      count.push_back(1);
      continue;
    }
    PointRadar& q = out[static_cast<std::size_t>(i)];
    const int n = ++count[static_cast<std::size_t>(i)];
    const float w = 1.0f / static_cast<float>(n);  // running means
    q.x += (p.x - q.x) * w;
    q.y += (p.y - q.y) * w;
    q.z += (p.z - q.z) * w;
    q.time_offset += (p.time_offset - q.time_offset) * w;
    q.cov_xx += (p.cov_xx - q.cov_xx) * w;
    q.cov_xy += (p.cov_xy - q.cov_xy) * w;
    q.cov_yy += (p.cov_yy - q.cov_yy) * w;
    q.power = std::max(q.power, p.power);
  }
  out.width = static_cast<std::uint32_t>(out.size());
  out.height = 1;
  out.is_dense = true;
}

}  // namespace radar_ndt
