#pragma once
// The target model and source points of WeightedNDT3D: cubic cells of side g, each the weighted
// probabilistic distribution of its points (paper, eq. 1, in 3D), the lookup from a point to the
// 2x2x2 block of cells nearest to it, and the weighted source of eq. (2) with its voxel merge.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <pcl/point_cloud.h>
#include <pcl/types.h>

#include "radar_ndt/registration/detail/cell_hash.h"
#include "radar_ndt/registration/detail/fast_exp.h"
#include "radar_ndt/registration/detail/point_fields.h"
#include "radar_ndt/registration/weighted_ndt_3d_settings.h"

namespace radar_ndt {
namespace detail {

/// A 3D integer cell coordinate in one 64-bit key, 21 bits an axis (±10⁶ cells).
inline std::uint64_t packKey3(std::int32_t ix, std::int32_t iy, std::int32_t iz) {
  constexpr std::uint64_t mask = (std::uint64_t(1) << 21) - 1;
  return ((static_cast<std::uint64_t>(static_cast<std::uint32_t>(ix)) & mask) << 42) |
         ((static_cast<std::uint64_t>(static_cast<std::uint32_t>(iy)) & mask) << 21) |
         (static_cast<std::uint64_t>(static_cast<std::uint32_t>(iz)) & mask);
}
/// Whether a scaled coordinate can be keyed (finite and within 21 bits).
inline bool keyable(double u) {
  return std::abs(u) < 1e6;
}

/// Open-addressing map from a packed 3D key to a value, insertion order kept by the caller (the
/// values are indices into its own vectors); linear probing, at most half full.
template <typename Value>
class KeyMap3D {
 public:
  explicit KeyMap3D(std::size_t expected = 16) { reset(expected); }
  /// Empties the map for about `expected` keys, keeping its memory when that is of the size
  /// needed (a sequence's scans and maps keep their sizes: nothing is allocated again).
  void reset(std::size_t expected) {
    std::size_t cap = 32;
    while (cap < 2 * expected) cap <<= 1;
    if (keys_.size() >= cap && keys_.size() <= 4 * cap) {
      std::fill(keys_.begin(), keys_.end(), kEmpty);
    } else {
      keys_.assign(cap, kEmpty);
      values_.resize(cap);
    }
    mask_ = keys_.size() - 1;
    size_ = 0;
  }
  /// The value of `key`, inserting `fresh` when absent (`inserted` tells which).
  Value& findOrInsert(std::uint64_t key, const Value& fresh, bool& inserted) {
    if (2 * (size_ + 1) > keys_.size()) grow();
    std::size_t h = hashKey(key) & mask_;
    while (keys_[h] != kEmpty) {
      if (keys_[h] == key) {
        inserted = false;
        return values_[h];
      }
      h = (h + 1) & mask_;
    }
    keys_[h] = key;
    values_[h] = fresh;
    ++size_;
    inserted = true;
    return values_[h];
  }
  const Value* find(std::uint64_t key) const {
    std::size_t h = hashKey(key) & mask_;
    while (keys_[h] != kEmpty) {
      if (keys_[h] == key) return &values_[h];
      h = (h + 1) & mask_;
    }
    return nullptr;
  }
  std::size_t size() const { return size_; }
  std::size_t memoryBytes() const { return keys_.capacity() * (sizeof(std::uint64_t) + sizeof(Value)); }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);  // no packed key has all 64 bits set
  void grow() {
    std::vector<std::uint64_t> keys;
    std::vector<Value> values;
    keys.swap(keys_);
    values.swap(values_);
    keys_.assign(2 * keys.size(), kEmpty);
    values_.resize(keys_.size());
    mask_ = keys_.size() - 1;
    size_ = 0;
    bool inserted = false;
    for (std::size_t i = 0; i < keys.size(); ++i)
      if (keys[i] != kEmpty) findOrInsert(keys[i], values[i], inserted);
  }
  std::vector<std::uint64_t> keys_;
  std::vector<Value> values_;
  std::size_t mask_ = 0;
  std::size_t size_ = 0;
};

/// One target distribution: weighted mean and inverse covariance.
struct NdtCell3D {
  Eigen::Vector3d mean;
  Eigen::Matrix3d inverse;  ///< Σ⁻¹
  double weight;            ///< Σ wᵢ of the points that built it
};

/// The up to eight cells around one grid vertex (−1: none).
struct CellBlock {
  std::int32_t slots[8];
};

/// The target's distributions at one cube size; a point is scored against the 2x2x2 block of
/// cells whose centres are nearest to it (those around the grid vertex nearest to it).
struct NdtGrid3D {
  double resolution = 0;
  std::vector<NdtCell3D> cells;
  KeyMap3D<CellBlock> index;
  /// The block of cells to score a point at q against, or nullptr.
  const CellBlock* cellsNear(const Eigen::Vector3d& q) const {
    const double u = q.x() / resolution + 0.5, v = q.y() / resolution + 0.5, w = q.z() / resolution + 0.5;
    if (!(keyable(u) && keyable(v) && keyable(w))) return nullptr;  // far away or NaN
    return index.find(packKey3(floorToInt(u), floorToInt(v), floorToInt(w)));
  }
  std::size_t memoryBytes() const { return cells.capacity() * sizeof(NdtCell3D) + index.memoryBytes(); }
};

/// A 3x3 symmetric matrix's upper triangle: xx, xy, xz, yy, yz, zz.
using Sym3 = Eigen::Matrix<double, 6, 1>;
inline Sym3 upperOf(const Eigen::Matrix3d& m) {
  Sym3 u;
  u << m(0, 0), m(0, 1), m(0, 2), m(1, 1), m(1, 2), m(2, 2);
  return u;
}
inline Sym3 outerUpper(const Eigen::Vector3d& d) {
  Sym3 u;
  u << d.x() * d.x(), d.x() * d.y(), d.x() * d.z(), d.y() * d.y(), d.y() * d.z(), d.z() * d.z();
  return u;
}
inline Eigen::Matrix3d fromUpper(const Sym3& u) {
  Eigen::Matrix3d m;
  m << u(0), u(1), u(2), u(1), u(3), u(4), u(2), u(4), u(5);
  return m;
}

/// A target point with its weight (eq. 1) and own covariance (upper triangle).
struct TargetPoint3D {
  Eigen::Vector3d p;
  double w;
  Sym3 cov;
};

inline bool usable3D(const Eigen::Vector3d& p, const Eigen::Matrix3d& cov) {
  return p.allFinite() && cov.allFinite() && cov(0, 0) >= 0 && cov(1, 1) >= 0 && cov(2, 2) >= 0;
}

/// The usable points of `target` with their eq. (1) weights w = max(p − s, 0), those of positive
/// weight only.
template <typename PointT>
void weightTargetPoints3D(const pcl::PointCloud<PointT>& target, double shift, std::vector<TargetPoint3D>& pts) {
  pts.clear();
  pts.reserve(target.size());
  for (const auto& pt : target) {
    const Eigen::Vector3d p(pt.x, pt.y, pt.z);
    const Eigen::Matrix3d cov = pointCovariance3D(pt);
    if (!usable3D(p, cov)) continue;
    const double w = std::max(0.0, static_cast<double>(pointPower(pt)) - shift);
    if (!(w > 0.0) || !std::isfinite(w)) continue;
    pts.push_back({p, w, upperOf(cov)});
  }
}
template <typename PointT>
std::vector<TargetPoint3D> weightTargetPoints3D(const pcl::PointCloud<PointT>& target, double shift) {
  std::vector<TargetPoint3D> pts;
  weightTargetPoints3D(target, shift, pts);
  return pts;
}

/// One cell's sums over its points, in point order: of w, w·d, w·d dᵀ and w·Σᵢ (upper triangles),
/// with d the point relative to the cell's corner (small, so the one-pass covariance stays well
/// conditioned).
struct CellSums3D {
  std::int32_t cx, cy, cz;
  int count = 0;
  double sw = 0;
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  Sym3 ss = Sym3::Zero();
  Sym3 sc = Sym3::Zero();
};

/// The cell of eq. (1) from its sums: the weighted mean and the inverse of the probabilistic
/// covariance Σ = Σ w [(p − μ)(p − μ)ᵀ + Σᵢ] / Σ w, its eigenvalues raised to at least `ratio` ×
/// the largest and to `abs_floor`.
inline NdtCell3D cellOf3D(const CellSums3D& a, double g, double ratio, double abs_floor) {
  const Eigen::Vector3d m = a.s / a.sw;
  const Eigen::Matrix3d cov = fromUpper(a.ss / a.sw - outerUpper(m) + a.sc / a.sw);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(cov);  // closed form: the floors below absorb its error on near-flat cells
  Eigen::Vector3d l = es.eigenvalues();
  const double lmax = std::max(l.maxCoeff(), abs_floor);
  for (int i = 0; i < 3; ++i) l(i) = std::max({l(i), ratio * lmax, abs_floor});
  NdtCell3D cell;
  cell.mean = Eigen::Vector3d(a.cx * g, a.cy * g, a.cz * g) + m;
  cell.inverse = es.eigenvectors() * l.cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
  cell.weight = a.sw;
  return cell;
}

/// Buffers a grid's build reuses from target to target.
struct GridScratch3D {
  std::vector<CellSums3D> sums;
  KeyMap3D<std::int32_t> slot_of;
};

/// Builds `grid` at cube size `g` from the weighted target points `pts`: per cell with at least
/// `min_points_per_cell` points (eq. 1), its weighted mean and probabilistic covariance; every
/// cell is listed under the eight grid vertices around it. Cells are in order of their first point.
inline void buildNdtGrid3D(const std::vector<TargetPoint3D>& pts, double g, const WeightedNDT3DSettings& settings,
                           NdtGrid3D& grid, GridScratch3D& scratch) {
  grid.resolution = g;
  grid.cells.clear();
  std::vector<CellSums3D>& sums = scratch.sums;
  sums.clear();
  KeyMap3D<std::int32_t>& slot_of = scratch.slot_of;
  slot_of.reset(pts.size() / 4 + 16);
  for (const TargetPoint3D& p : pts) {
    const Eigen::Vector3d u = p.p / g;
    if (!(keyable(u.x()) && keyable(u.y()) && keyable(u.z()))) continue;
    const std::int32_t cx = floorToInt(u.x()), cy = floorToInt(u.y()), cz = floorToInt(u.z());
    bool inserted = false;
    const std::int32_t i = slot_of.findOrInsert(packKey3(cx, cy, cz), static_cast<std::int32_t>(sums.size()), inserted);
    if (inserted) {
      sums.emplace_back();
      sums.back().cx = cx;
      sums.back().cy = cy;
      sums.back().cz = cz;
    }
    CellSums3D& a = sums[static_cast<std::size_t>(i)];
    const Eigen::Vector3d d = p.p - Eigen::Vector3d(cx * g, cy * g, cz * g);
    ++a.count;
    a.sw += p.w;
    a.s += p.w * d;
    a.ss += p.w * outerUpper(d);
    a.sc += p.w * p.cov;
  }
  // Relative and absolute eigenvalue floors: (1 % of g)² keeps flat cells (a wall, the ground)
  // invertible.
  const double abs_floor = (0.01 * g) * (0.01 * g);
  grid.index.reset(4 * sums.size() + 16);
  for (const CellSums3D& a : sums) {
    if (a.count < settings.min_points_per_cell) continue;
    const auto idx = static_cast<std::int32_t>(grid.cells.size());
    grid.cells.push_back(cellOf3D(a, g, settings.eigenvalue_ratio, abs_floor));
    // Cell (cx, cy, cz) has vertices (cx..cx+1, cy..cy+1, cz..cz+1); each lists its 2x2x2 block.
    for (int k = 0; k < 8; ++k) {
      CellBlock none;
      std::fill(std::begin(none.slots), std::end(none.slots), -1);
      bool inserted = false;
      CellBlock& block = grid.index.findOrInsert(packKey3(a.cx + (k & 1), a.cy + ((k >> 1) & 1), a.cz + ((k >> 2) & 1)),
                                                 none, inserted);
      *std::find(std::begin(block.slots), std::end(block.slots), -1) = idx;
    }
  }
}

/// The same from a cloud: its points weighted by eq. (1) first.
template <typename PointT>
void buildNdtGrid3D(const pcl::PointCloud<PointT>& target, double g, const WeightedNDT3DSettings& settings,
                    NdtGrid3D& grid) {
  GridScratch3D scratch;
  buildNdtGrid3D(weightTargetPoints3D(target, settings.power_shift), g, settings, grid, scratch);
}

/// A source point reduced to what the cost needs: position and the weight of eq. (2).
struct WeightedPoint3D {
  Eigen::Vector3d p;
  double w;
};

/// The usable points of `cloud` at `indices` with their eq. (2) weights
/// w = max(p − s, 0) · exp(−½(σx + σy + σz)); points of zero or non-finite weight are left out.
template <typename PointT>
void weightSourcePoints3D(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices, double shift,
                          std::vector<WeightedPoint3D>& out) {
  out.clear();
  out.reserve(indices.size());
  for (const auto i : indices) {
    const PointT& pt = cloud[i];
    const Eigen::Vector3d p(pt.x, pt.y, pt.z);
    const Eigen::Matrix3d cov = pointCovariance3D(pt);
    if (!usable3D(p, cov)) continue;
    const double sigma_sum = std::sqrt(cov(0, 0)) + std::sqrt(cov(1, 1)) + std::sqrt(cov(2, 2));
    // Far from 0 the factor underflows to 0 and the point drops out, as it should.
    const double w = std::max(0.0, static_cast<double>(pointPower(pt)) - shift) * std::exp(-0.5 * sigma_sum);
    if (!(w > 0.0) || !std::isfinite(w)) continue;
    out.push_back({p, w});
  }
}

/// Buffers the merge reuses from scan to scan.
/// Points in one cube of side `v` (> 0) become one point at their weighted centroid carrying
/// their summed weight, in order of each cube's first point; points that cannot be keyed drop.
struct SourceScratch3D {
  std::vector<WeightedPoint3D> merged;
  KeyMap3D<std::int32_t> slot_of;
};
inline void mergeSourceVoxels3D(double v, std::vector<WeightedPoint3D>& points, SourceScratch3D& scratch) {
  if (!(v > 0) || points.size() <= 1) return;
  std::vector<WeightedPoint3D>& merged = scratch.merged;  // swapped with `points` below: the two take turns
  merged.clear();
  merged.reserve(points.size());
  KeyMap3D<std::int32_t>& slot_of = scratch.slot_of;
  slot_of.reset(points.size());
  for (const WeightedPoint3D& p : points) {
    const Eigen::Vector3d u = p.p / v;
    if (!(keyable(u.x()) && keyable(u.y()) && keyable(u.z()))) continue;
    bool inserted = false;
    const std::int32_t i = slot_of.findOrInsert(packKey3(floorToInt(u.x()), floorToInt(u.y()), floorToInt(u.z())),
                                                static_cast<std::int32_t>(merged.size()), inserted);
    if (inserted) merged.push_back({Eigen::Vector3d::Zero(), 0.0});
    WeightedPoint3D& m = merged[static_cast<std::size_t>(i)];
    m.p += p.w * p.p;
    m.w += p.w;
  }
  for (auto& m : merged) m.p /= m.w;
  points.swap(merged);
}

}  // namespace detail
}  // namespace radar_ndt
