#pragma once
// The source scan as WeightedNDT2D's cost uses it: each point reduced to (x, y, w) with the
// matching weight of the paper's eq. (2), optionally merged into small voxels.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/types.h>

#include "radar_ndt/registration/detail/cell_hash.h"
#include "radar_ndt/registration/detail/fast_exp.h"
#include "radar_ndt/registration/detail/point_fields.h"

namespace radar_ndt {
namespace detail {

/// A source point reduced to what the cost needs: position, weight and time offset within its
/// sweep (s; used only when the sweep's motion is part of the match, detail/sweep_cost.h).
struct WeightedPoint2D {
  double x, y, w;
  double t = 0;
};

/// Buffers the voxel merge reuses from scan to scan (so nothing is allocated while scans keep
/// their size).
struct SourceVoxelScratch {
  std::vector<std::int32_t> keys;       ///< each point's voxel key
  std::vector<std::int32_t> table;      ///< the dense table of voxel slots
  std::vector<WeightedPoint2D> merged;  ///< the merged points (then the previous source)
  std::vector<WeightedPoint2D> late;    ///< a sweep's later half (mergeSourceVoxelsByHalfSweep)
};

/// The usable points of `cloud` at `indices` with their eq. (2) weights
/// w = max(p − s, 0) · exp(−½(σx + σy)); points of zero or non-finite weight are left out.
template <typename PointT>
void weightSourcePoints(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices, double shift,
                        std::vector<WeightedPoint2D>& out) {
  out.clear();
  out.reserve(indices.size());
  for (const auto i : indices) {
    const PointT& p = cloud[i];
    const Eigen::Vector3d cov = pointCovariance(p);
    if (!usable(p.x, p.y, cov)) continue;
    const double w = std::max(0.0, static_cast<double>(pointPower(p)) - shift) *
                     expNegative(-0.5 * (std::sqrt(cov.x()) + std::sqrt(cov.z())));
    if (!(w > 0.0) || !std::isfinite(w)) continue;
    out.push_back({p.x, p.y, w, pointTimeOffset(p)});
  }
}

/// The extent of the voxel keys, inclusive.
struct KeyExtent {
  std::int32_t x0 = std::numeric_limits<std::int32_t>::max(), y0 = std::numeric_limits<std::int32_t>::max();
  std::int32_t x1 = std::numeric_limits<std::int32_t>::min(), y1 = std::numeric_limits<std::int32_t>::min();
};

/// Each point's voxel key (side v) into `keys` (x, y pairs) and the keys' extent, in one pass;
/// points beyond any sensible extent cannot be keyed and are dropped (the kept keep their order).
inline KeyExtent keyVoxels(double v, std::vector<WeightedPoint2D>& points, std::vector<std::int32_t>& keys) {
  keys.resize(2 * points.size());
  KeyExtent e;
  std::size_t n = 0;
  for (const auto& p : points) {
    const double u = p.x / v, w = p.y / v;
    if (!(std::abs(u) < 1e9 && std::abs(w) < 1e9)) continue;
    const std::int32_t kx = floorToInt(u), ky = floorToInt(w);
    points[n] = p;
    keys[2 * n] = kx;
    keys[2 * n + 1] = ky;
    ++n;
    e.x0 = std::min(e.x0, kx);
    e.x1 = std::max(e.x1, kx);
    e.y0 = std::min(e.y0, ky);
    e.y1 = std::max(e.y1, ky);
  }
  points.resize(n);
  return e;
}

/// The merged slot of each point, in order of first point: from a dense table of voxel slots
/// when the extent is compact (a scan, a submap), filled in far less time than hashing the points
/// takes (at most 64 slots a point beyond 1 MB, and never over 16 MB), else from a hash.
/// Neighbouring points share table rows where a hash scatters them; both keep first-seen order, so
/// the merged points are the same either way. Calls add(slot, point, new_slot).
template <typename Add>
void forEachVoxelSlot(const std::vector<WeightedPoint2D>& points, const std::vector<std::int32_t>& keys,
                      const KeyExtent& e, SourceVoxelScratch& scratch, Add&& add) {
  const std::size_t n = points.size();
  const std::int64_t width = std::int64_t(e.x1) - e.x0 + 1, height = std::int64_t(e.y1) - e.y0 + 1;
  const std::int64_t slots = width * height;
  std::int32_t next = 0;
  if (n > 0 && slots <= std::min<std::int64_t>(64 * static_cast<std::int64_t>(n) + (1 << 18), 1 << 22)) {
    scratch.table.assign(static_cast<std::size_t>(slots), -1);
    for (std::size_t i = 0; i < n; ++i) {
      std::int32_t& slot =
          scratch.table[static_cast<std::size_t>(std::int64_t(keys[2 * i] - e.x0) * height + (keys[2 * i + 1] - e.y0))];
      const bool fresh = slot < 0;
      if (fresh) slot = next++;
      add(slot, points[i], fresh);
    }
    return;
  }
  KeyIndexMap map(n);
  for (std::size_t i = 0; i < n; ++i) {
    bool inserted = false;
    const std::int32_t slot = map.findOrInsert(keys[2 * i], keys[2 * i + 1], next, inserted);
    if (inserted) ++next;
    add(slot, points[i], inserted);
  }
}

/// Points in one voxel of side `v` (> 0) become one point at their weighted centroid carrying
/// their summed weight, in order of each voxel's first point. The cost Σ wᵢ exp(−½ qᵢᵀΣ⁻¹qᵢ)
/// barely changes while the voxel is small against the cells' spread; evaluation time drops with
/// the point count. Points beyond any sensible extent cannot be keyed and are dropped.
inline void mergeSourceVoxels(double v, std::vector<WeightedPoint2D>& points, SourceVoxelScratch& scratch) {
  if (!(v > 0) || points.size() <= 1) return;
  const KeyExtent extent = keyVoxels(v, points, scratch.keys);
  // (Σ w x, Σ w y, Σ w), in order of first point; swapped with `points` below, so the two buffers
  // take turns and neither is allocated again while scans keep their size.
  std::vector<WeightedPoint2D>& merged = scratch.merged;
  merged.clear();
  merged.reserve(points.size());
  forEachVoxelSlot(points, scratch.keys, extent, scratch, [&](std::int32_t slot, const WeightedPoint2D& p, bool fresh) {
    if (fresh) merged.push_back({0, 0, 0, 0});
    auto& m = merged[static_cast<std::size_t>(slot)];
    m.x += p.w * p.x;
    m.y += p.w * p.y;
    m.w += p.w;
    m.t += p.w * p.t;
  });
  for (auto& m : merged) {
    m.x /= m.w;
    m.y /= m.w;
    m.t /= m.w;
  }
  points.swap(merged);
}

/// mergeSourceVoxels for a sweep whose points carry their time offsets: the points of the earlier
/// and the later half of the offsets' span are merged apart, the earlier half's first. A sweep
/// starts and ends at one azimuth, so voxels there hold points a whole sweep apart in time, whose
/// mean time would place them where neither was; elsewhere a voxel spans a few milliseconds.
inline void mergeSourceVoxelsByHalfSweep(double v, std::vector<WeightedPoint2D>& points, SourceVoxelScratch& scratch) {
  if (points.empty()) return;
  double t0 = points.front().t, t1 = t0;
  for (const auto& p : points) {
    t0 = std::min(t0, p.t);
    t1 = std::max(t1, p.t);
  }
  const double mid = 0.5 * (t0 + t1);
  std::vector<WeightedPoint2D>& late = scratch.late;
  late.clear();
  std::size_t n = 0;
  for (const auto& p : points) {
    if (p.t > mid)
      late.push_back(p);
    else
      points[n++] = p;
  }
  points.resize(n);
  mergeSourceVoxels(v, points, scratch);
  mergeSourceVoxels(v, late, scratch);
  points.insert(points.end(), late.begin(), late.end());
}

}  // namespace detail
}  // namespace radar_ndt
