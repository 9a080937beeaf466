#include "radar_ndt/evaluation/top_view_map.h"
#include "radar_ndt/io/png_image.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace radar_ndt {

namespace {
std::uint64_t key(std::int32_t i, std::int32_t j) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) | static_cast<std::uint32_t>(j);
}
std::int32_t keyI(std::uint64_t k) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(k >> 32));
}
std::int32_t keyJ(std::uint64_t k) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(k & 0xffffffffu));
}
}  // namespace

TopViewMap::TopViewMap(double resolution) : resolution_(resolution) {
  if (!(resolution > 0) || !std::isfinite(resolution))
    throw std::invalid_argument("TopViewMap: resolution must be > 0");
}

void TopViewMap::add(const pcl::PointCloud<PointRadar>& cloud, const Pose2& pose) {
  poses_.push_back(pose);
  const double c = std::cos(pose.z()), s = std::sin(pose.z());
  for (const auto& p : cloud) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
    const double x = pose.x() + c * p.x - s * p.y, y = pose.y() + s * p.x + c * p.y;
    const double u = std::floor(x / resolution_), v = std::floor(y / resolution_);
    if (std::abs(u) > 1e9 || std::abs(v) > 1e9) continue;
    float& cell = cells_[key(static_cast<std::int32_t>(u), static_cast<std::int32_t>(v))];
    cell = std::max(cell, std::isfinite(p.power) ? std::max(p.power, 0.05f) : 1.0f);
  }
}

void TopViewMap::writePng(const std::string& path, int max_side) const {
  if (cells_.empty() && poses_.empty()) throw std::logic_error("TopViewMap::writePng: nothing was added");
  // Bounds in cell indices: i along x (up in the image), j along y (left in the image).
  std::int64_t i0 = std::numeric_limits<std::int64_t>::max(), i1 = std::numeric_limits<std::int64_t>::min(), j0 = i0,
               j1 = i1;
  auto grow = [&](std::int64_t i, std::int64_t j) {
    i0 = std::min(i0, i);
    i1 = std::max(i1, i);
    j0 = std::min(j0, j);
    j1 = std::max(j1, j);
  };
  for (const auto& [k, p] : cells_) grow(keyI(k), keyJ(k));
  for (const auto& q : poses_)
    grow(static_cast<std::int64_t>(std::floor(q.x() / resolution_)),
         static_cast<std::int64_t>(std::floor(q.y() / resolution_)));
  const std::int64_t margin = 10;
  i0 -= margin, i1 += margin, j0 -= margin, j1 += margin;
  const std::int64_t extent = std::max(i1 - i0 + 1, j1 - j0 + 1);
  const std::int64_t scale =
      std::max<std::int64_t>(1, (extent + max_side - 1) / std::max(1, max_side));  // cells per pixel
  const int height = static_cast<int>((i1 - i0 + 1 + scale - 1) / scale),
            width = static_cast<int>((j1 - j0 + 1 + scale - 1) / scale);
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3, 0);
  auto pixel = [&](std::int64_t i, std::int64_t j) -> std::uint8_t* {
    const std::int64_t row = (i1 - i) / scale, col = (j1 - j) / scale;  // +x up, +y left
    if (row < 0 || col < 0 || row >= height || col >= width) return nullptr;
    return &rgb[(static_cast<std::size_t>(row) * width + static_cast<std::size_t>(col)) * 3];
  };
  for (const auto& [k, p] : cells_) {
    std::uint8_t* px = pixel(keyI(k), keyJ(k));
    if (!px) continue;
    // Gamma-brightened so weak returns stay visible.
    const auto g = static_cast<std::uint8_t>(std::lround(255.0 * std::sqrt(std::min(1.0f, std::max(0.0f, p)))));
    px[0] = px[1] = px[2] = std::max(px[0], g);
  }
  for (std::size_t n = 0; n < poses_.size(); ++n) {
    // The trajectory: a red line between consecutive poses (a dot for a single one).
    const Pose2 a = poses_[n], b = poses_[std::min(n + 1, poses_.size() - 1)];
    const double len = (b.head<2>() - a.head<2>()).norm();
    const int steps = std::max(1, static_cast<int>(std::ceil(len / (0.5 * resolution_))));
    for (int s = 0; s <= steps; ++s) {
      const Eigen::Vector2d q = a.head<2>() + (b.head<2>() - a.head<2>()) * (static_cast<double>(s) / steps);
      if (std::uint8_t* px = pixel(static_cast<std::int64_t>(std::floor(q.x() / resolution_)),
                                   static_cast<std::int64_t>(std::floor(q.y() / resolution_)))) {
        px[0] = 255;
        px[1] = px[2] = 0;
      }
    }
  }
  radar_ndt::writePng(path, width, height, 3, rgb.data(), 6);
}

}  // namespace radar_ndt
