#pragma once
// The target model of WeightedNDT2D: square cells of side g, each the weighted probabilistic
// distribution of its points (paper, eq. 1; Hong & Lee 2017), and the lookup from a point to the
// cells it is scored against.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <pcl/point_cloud.h>

#include "radar_ndt/registration/detail/cell_hash.h"
#include "radar_ndt/registration/detail/point_fields.h"
#include "radar_ndt/registration/weighted_ndt_2d_settings.h"

namespace radar_ndt {
namespace detail {

/// One target distribution: weighted mean and inverse covariance (upper triangle).
struct NdtCell {
  double mx, my;         ///< μ
  double ixx, ixy, iyy;  ///< Σ⁻¹
  double weight;         ///< Σ wᵢ of the points that built it
};

/// The target's distributions at one grid size, with the lookup from a point to its cells.
struct NdtGrid {
  double resolution = 0;
  CellLookup lookup = CellLookup::Neighbours;
  std::vector<NdtCell> cells;
  CellIndexHash index;
  /// Lookup keys are floor(x · key_scale + key_shift): the nearest grid vertex (Neighbours) or the
  /// half-size cell (OverlappingGrids).
  double key_scale = 1, key_shift = 0;
  void setLookup(double g, CellLookup l) {
    resolution = g;
    lookup = l;
    key_scale = l == CellLookup::Neighbours ? 1.0 / g : 2.0 / g;
    key_shift = l == CellLookup::Neighbours ? 0.5 : 0.0;
  }
  /// Up to four cells to score a point at (x, y) against; returns the slot array or nullptr.
  inline const std::int32_t* cellsNear(double x, double y) const {
    const double u = x * key_scale + key_shift, v = y * key_scale + key_shift;
    if (!(std::abs(u) < 1e9 && std::abs(v) < 1e9)) return nullptr;  // far away or NaN: no key
    return index.find(static_cast<std::int32_t>(std::floor(u)), static_cast<std::int32_t>(std::floor(v)));
  }
  std::size_t memoryBytes() const { return cells.capacity() * sizeof(NdtCell) + index.memoryBytes(); }
};

/// A target point with a positive weight (eq. 1) and its own covariance (xx, xy, yy).
struct TargetPoint {
  double x, y, w;
  Eigen::Vector3d cov;
};

/// The usable points of `target` with their eq. (1) weights w = max(p − s, 0), those of positive
/// weight only.
template <typename PointT>
std::vector<TargetPoint> weightTargetPoints(const pcl::PointCloud<PointT>& target,
                                            const WeightedNDT2DSettings& settings) {
  std::vector<TargetPoint> pts;
  pts.reserve(target.size());
  for (const auto& p : target) {
    const Eigen::Vector3d cov = pointCovariance(p);
    if (!usable(p.x, p.y, cov)) continue;
    const double w = std::max(0.0, static_cast<double>(pointPower(p)) - settings.power_shift);
    if (!(w > 0.0) || !std::isfinite(w)) continue;
    pts.push_back({p.x, p.y, w, cov});
  }
  return pts;
}

/// One cell's sums over its points, in point order: of w, w·d, w·d dᵀ and w·Σᵢ with d the point
/// relative to the cell's corner (|d| < g keeps the one-pass covariance well conditioned).
struct CellSums {
  std::int32_t cx, cy;
  int count;
  double sw, sx, sy, sxx, sxy, syy, cxx, cxy, cyy;
};

/// The points' sums per cell of side g whose grid is shifted by (ox, oy), cells in order of
/// their first point (deterministic).
inline std::vector<CellSums> sumCells(const std::vector<TargetPoint>& pts, double g, double ox, double oy) {
  std::vector<CellSums> acc;
  acc.reserve(pts.size() / 4 + 16);
  KeyIndexMap map(pts.size() / 4 + 16);
  for (const TargetPoint& p : pts) {
    const double u = (p.x - ox) / g, v = (p.y - oy) / g;
    if (!(std::abs(u) < 1e9 && std::abs(v) < 1e9)) continue;  // beyond any sensible extent
    const std::int32_t cx = floorToInt(u), cy = floorToInt(v);
    bool inserted = false;
    const std::int32_t i = map.findOrInsert(cx, cy, static_cast<std::int32_t>(acc.size()), inserted);
    if (inserted) acc.push_back(CellSums{cx, cy, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
    CellSums& a = acc[static_cast<std::size_t>(i)];
    const double dx = p.x - (cx * g + ox), dy = p.y - (cy * g + oy);
    ++a.count;
    a.sw += p.w;
    a.sx += p.w * dx;
    a.sy += p.w * dy;
    a.sxx += p.w * dx * dx;
    a.sxy += p.w * dx * dy;
    a.syy += p.w * dy * dy;
    a.cxx += p.w * p.cov.x();
    a.cxy += p.w * p.cov.y();
    a.cyy += p.w * p.cov.z();
  }
  return acc;
}

/// The cell of eq. (1) from its sums: the weighted mean and the inverse of the probabilistic
/// covariance Σ = Σ w [(p − μ)(p − μ)ᵀ + Σᵢ] / Σ w, its small eigenvalue raised to at least
/// `ratio` × the large one and both to at least `abs_floor`.
inline NdtCell cellOf(const CellSums& a, double g, double ox, double oy, double ratio, double abs_floor) {
  const double mdx = a.sx / a.sw, mdy = a.sy / a.sw;  // mean relative to the corner
  const double cxx = std::max(0.0, a.sxx / a.sw - mdx * mdx) + a.cxx / a.sw;
  const double cxy = a.sxy / a.sw - mdx * mdy + a.cxy / a.sw;
  const double cyy = std::max(0.0, a.syy / a.sw - mdy * mdy) + a.cyy / a.sw;
  // Eigen-decomposition of the 2x2 covariance, closed form; floor the small eigenvalue.
  const double tr_half = 0.5 * (cxx + cyy);
  const double disc = std::sqrt(std::max(0.0, 0.25 * (cxx - cyy) * (cxx - cyy) + cxy * cxy));
  double l1 = tr_half + disc, l2 = tr_half - disc;
  l1 = std::max(l1, abs_floor);
  l2 = std::max({l2, ratio * l1, abs_floor});
  double vx, vy;  // unit eigenvector of the large eigenvalue
  if (std::abs(cxy) > 1e-12 * (std::abs(cxx) + std::abs(cyy))) {
    vx = (tr_half + disc) - cyy;
    vy = cxy;
  } else if (cxx >= cyy) {
    vx = 1;
    vy = 0;
  } else {
    vx = 0;
    vy = 1;
  }
  const double n = std::hypot(vx, vy);
  vx /= n;
  vy /= n;
  // Σ⁻¹ = v vᵀ / l1 + u uᵀ / l2, u ⟂ v
  const double ia = 1.0 / l1, ic = 1.0 / l2;
  NdtCell cell;
  cell.mx = a.cx * g + ox + mdx;
  cell.my = a.cy * g + oy + mdy;
  cell.ixx = ia * vx * vx + ic * vy * vy;
  cell.ixy = (ia - ic) * vx * vy;
  cell.iyy = ia * vy * vy + ic * vx * vx;
  cell.weight = a.sw;
  return cell;
}

/// Lists cell `idx` (cell (cx, cy) of grid k, half-cell offsets kx, ky) under the lookup keys that
/// reach it.
inline void indexCell(NdtGrid& grid, std::int32_t cx, std::int32_t cy, int kx, int ky, std::int32_t idx) {
  if (grid.lookup == CellLookup::Neighbours) {
    // Lookup key: the grid vertex nearest the query point; cell (cx, cy) has vertices
    // (cx..cx+1, cy..cy+1), so each vertex lists the 2x2 block of cells around it.
    grid.index.add(cx, cy, idx);
    grid.index.add(cx + 1, cy, idx);
    grid.index.add(cx, cy + 1, idx);
    grid.index.add(cx + 1, cy + 1, idx);
  } else {
    // Lookup key: the half-size cell the query point falls in; this cell of grid k covers
    // half-cells (2cx + kx .. 2cx + kx + 1, 2cy + ky .. 2cy + ky + 1).
    const std::int32_t hx = 2 * cx + kx, hy = 2 * cy + ky;
    grid.index.add(hx, hy, idx);
    grid.index.add(hx + 1, hy, idx);
    grid.index.add(hx, hy + 1, idx);
    grid.index.add(hx + 1, hy + 1, idx);
  }
}

/// Builds `grid` at size `g` from `target`: per cell with at least `min_points_per_cell` points of
/// positive weight wᵢ = max(pᵢ − s, 0) (eq. 1), the weighted mean μ = Σ wᵢpᵢ / Σ wᵢ and the
/// probabilistic covariance Σ = Σ wᵢ[(pᵢ−μ)(pᵢ−μ)ᵀ + Σᵢ] / Σ wᵢ, its small eigenvalue floored.
template <typename PointT>
void buildNdtGrid(const pcl::PointCloud<PointT>& target, double g, const WeightedNDT2DSettings& settings,
                  NdtGrid& grid) {
  grid.setLookup(g, settings.cell_lookup);
  grid.cells.clear();
  grid.index.clear();
  const std::vector<TargetPoint> pts = weightTargetPoints(target, settings);
  // Relative and absolute eigenvalue floors: (1 % of g)² keeps single-line cells invertible.
  const double abs_floor = (0.01 * g) * (0.01 * g);
  const int n_grids = settings.cell_lookup == CellLookup::OverlappingGrids ? 4 : 1;
  for (int k = 0; k < n_grids; ++k) {
    const int kx = k & 1, ky = (k >> 1) & 1;  // half-cell offsets of this grid
    const double ox = 0.5 * g * kx, oy = 0.5 * g * ky;
    for (const CellSums& a : sumCells(pts, g, ox, oy)) {
      if (a.count < settings.min_points_per_cell) continue;
      const auto idx = static_cast<std::int32_t>(grid.cells.size());
      grid.cells.push_back(cellOf(a, g, ox, oy, settings.eigenvalue_ratio, abs_floor));
      indexCell(grid, a.cx, a.cy, kx, ky, idx);
    }
  }
  grid.index.finalize();
}

}  // namespace detail
}  // namespace radar_ndt
