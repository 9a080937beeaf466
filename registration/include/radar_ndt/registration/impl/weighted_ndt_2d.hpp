#pragma once
// Implementation of radar_ndt::WeightedNDT2D. Included by the library's instantiation unit, and by
// users who need point types other than pcl::PointXYZ, pcl::PointXYZI and radar_ndt::PointRadar.

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstring>
#include <numeric>

#include <Eigen/Eigenvalues>
#include <pcl/common/transforms.h>
#include <pcl/console/print.h>
#include <pcl/type_traits.h>

#include "radar_ndt/registration/weighted_ndt_2d.h"
#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace detail {

/// Power used for the weights: PointRadar's `power`, PointXYZI's `intensity`, else 1.
template <typename PointT>
inline float pointPower(const PointT& p) {
  if constexpr (pcl::traits::has_field<PointT, pcl::fields::power>::value)
    return p.power;
  else if constexpr (pcl::traits::has_field<PointT, pcl::fields::intensity>::value)
    return p.intensity;
  else {
    (void)p;
    return 1.0f;
  }
}

/// The point's own 2x2 position covariance, zero when the type has none.
template <typename PointT>
inline Eigen::Vector3d pointCovariance(const PointT& p) {  // (xx, xy, yy)
  if constexpr (pcl::traits::has_field<PointT, pcl::fields::cov_xx>::value)
    return Eigen::Vector3d(p.cov_xx, p.cov_xy, p.cov_yy);
  else {
    (void)p;
    return Eigen::Vector3d::Zero();
  }
}

template <typename PointT>
inline void rotateCovariance(PointT& p, const Eigen::Matrix2d& R) {
  if constexpr (pcl::traits::has_field<PointT, pcl::fields::cov_xx>::value) {
    Eigen::Matrix2d C;
    C << p.cov_xx, p.cov_xy, p.cov_xy, p.cov_yy;
    const Eigen::Matrix2d Cr = R * C * R.transpose();
    p.cov_xx = static_cast<float>(Cr(0, 0));
    p.cov_xy = static_cast<float>(Cr(0, 1));
    p.cov_yy = static_cast<float>(Cr(1, 1));
  } else {
    (void)p;
    (void)R;
  }
}

/// A usable point: finite position and covariance, covariance not negative on the diagonal.
inline bool usable(double x, double y, const Eigen::Vector3d& cov) {
  return std::isfinite(x) && std::isfinite(y) && cov.allFinite() && cov.x() >= 0 && cov.z() >= 0;
}

inline std::int32_t floorToInt(double v) { return static_cast<std::int32_t>(std::floor(v)); }

/// exp(x) for x in [-700, 0] (the Gaussian scores and the point weights), relative error below
/// 1e-8; below -700 (and NaN) as at -700, about 1e-304: x·log2(e) split into an integer k and f
/// in [-1/2, 1/2], 2^f by its Taylor series to degree 7, 2^k put in the exponent bits. Inline and
/// about a third of libm's exp in this loop; a pure function, so results stay deterministic.
#if defined(__GNUC__) || defined(__clang__)
#define RADAR_NDT_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define RADAR_NDT_ALWAYS_INLINE inline
#endif
RADAR_NDT_ALWAYS_INLINE double expNegative(double x) {
  x = x >= -700.0 ? x : -700.0;  // branch-free, so the function stays inlined
  const double t = x * 1.4426950408889634;  // log2(e), t <= 0
  const double k = static_cast<double>(static_cast<std::int64_t>(t - 0.5));  // truncation: t rounded
  const double f = (t - k) * 0.6931471805599453;  // e^f = 2^(t - k)
  // Degree 7 in Estrin's form (three dependent multiply-adds instead of ten in Horner's): for
  // |f| <= ln2/2 the truncation error is below f⁸/8!·e^|f| < 8e-9 relative.
  const double f2 = f * f, f4 = f2 * f2;
  const double p = ((1.0 + f) + f2 * (0.5 + f * (1.0 / 6.0))) +
                   f4 * (((1.0 / 24.0) + f * (1.0 / 120.0)) + f2 * ((1.0 / 720.0) + f * (1.0 / 5040.0)));
  const std::uint64_t bits = static_cast<std::uint64_t>(static_cast<std::int64_t>(k) + 1023) << 52;
  double scale;
  std::memcpy(&scale, &bits, sizeof(scale));
  return p * scale;
}

}  // namespace detail

template <typename PointSource, typename PointTarget>
WeightedNDT2D<PointSource, PointTarget>::WeightedNDT2D() {
  reg_name_ = "WeightedNDT2D";
  max_iterations_ = 35;
  transformation_epsilon_ = 1e-6;                      // (1 mm)² of translation increment
  transformation_rotation_epsilon_ = std::cos(1e-4);   // 0.1 mrad of rotation increment
  this->tree_.reset(new detail::LazyKdTree<PointTarget>());
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setInputTarget(const PointCloudTargetConstPtr& cloud) {
  Base::setInputTarget(cloud);
  buildTargetModel();
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setResolutions(const std::vector<float>& sizes) {
  if (sizes.empty() || std::any_of(sizes.begin(), sizes.end(), [](float g) { return !(g > 0.0f) || !std::isfinite(g); })) {
    PCL_ERROR("[radar_ndt::%s::setResolutions] grid sizes must be positive and finite; keeping the old ones\n",
              reg_name_.c_str());
    return;
  }
  resolutions_ = sizes;
  model_stale_ = true;  // rebuilt at the next setInputTarget() or align()
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setPowerShift(float s) {
  if (!std::isfinite(s)) {
    PCL_ERROR("[radar_ndt::%s::setPowerShift] shift must be finite\n", reg_name_.c_str());
    return;
  }
  power_shift_ = s;
  model_stale_ = true;  // rebuilt at the next setInputTarget() or align()
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setEigenvalueRatio(double ratio) {
  if (!(ratio > 0.0 && ratio <= 1.0)) {
    PCL_ERROR("[radar_ndt::%s::setEigenvalueRatio] ratio must be in (0, 1]\n", reg_name_.c_str());
    return;
  }
  eigen_ratio_ = ratio;
  model_stale_ = true;  // rebuilt at the next setInputTarget() or align()
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setMinPointsPerCell(int n) {
  min_points_per_cell_ = std::max(1, n);
  model_stale_ = true;  // rebuilt at the next setInputTarget() or align()
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::setCellLookup(CellLookup lookup) {
  lookup_ = lookup;
  model_stale_ = true;  // rebuilt at the next setInputTarget() or align()
}

template <typename PointSource, typename PointTarget>
std::size_t WeightedNDT2D<PointSource, PointTarget>::getTargetModelBytes() const {
  std::size_t bytes = 0;
  for (const auto& g : grids_) bytes += g.cells.capacity() * sizeof(detail::NdtCell) + g.index.memoryBytes();
  return bytes;
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::buildTargetModel() {
  grids_.clear();
  model_stale_ = false;
  if (!target_) return;
  grids_.resize(resolutions_.size());
  for (std::size_t i = 0; i < resolutions_.size(); ++i) buildGrid(grids_[i], resolutions_[i]);
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::buildGrid(detail::NdtGrid& grid, double g) const {
  grid.setLookup(g, lookup_);
  grid.cells.clear();
  grid.index.clear();

  // Target points with a positive weight, eq. (1): w = max(p − s, 0).
  struct TargetPoint {
    double x, y, w;
    Eigen::Vector3d cov;
  };
  std::vector<TargetPoint> pts;
  pts.reserve(target_->size());
  for (const auto& p : *target_) {
    const Eigen::Vector3d cov = detail::pointCovariance(p);
    if (!detail::usable(p.x, p.y, cov)) continue;
    const double w = std::max(0.0, static_cast<double>(detail::pointPower(p)) - power_shift_);
    if (!(w > 0.0) || !std::isfinite(w)) continue;
    pts.push_back({p.x, p.y, w, cov});
  }

  // Relative and absolute eigenvalue floors: (1 % of g)² keeps single-line cells invertible.
  const double abs_floor = (0.01 * g) * (0.01 * g);
  const int n_grids = lookup_ == CellLookup::OverlappingGrids ? 4 : 1;

  // Per cell, one pass in point order (deterministic): sums of w, w·d, w·d dᵀ and w·Σᵢ with d the
  // point relative to its cell's corner (|d| < g keeps the one-pass covariance well conditioned).
  struct Accumulator {
    std::int32_t cx, cy;
    int count;
    double sw, sx, sy, sxx, sxy, syy, cxx, cxy, cyy;
  };
  for (int k = 0; k < n_grids; ++k) {
    const int kx = k & 1, ky = (k >> 1) & 1;  // half-cell offsets of this grid
    const double ox = 0.5 * g * kx, oy = 0.5 * g * ky;
    std::vector<Accumulator> acc;
    acc.reserve(pts.size() / 4 + 16);
    detail::KeyIndexMap map(pts.size() / 4 + 16);
    for (const TargetPoint& p : pts) {
      const double u = (p.x - ox) / g, v = (p.y - oy) / g;
      if (!(std::abs(u) < 1e9 && std::abs(v) < 1e9)) continue;  // beyond any sensible extent
      const std::int32_t cx = detail::floorToInt(u), cy = detail::floorToInt(v);
      bool inserted = false;
      const std::int32_t i = map.findOrInsert(cx, cy, static_cast<std::int32_t>(acc.size()), inserted);
      if (inserted) acc.push_back(Accumulator{cx, cy, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
      Accumulator& a = acc[static_cast<std::size_t>(i)];
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
    for (const Accumulator& a : acc) {
      if (a.count < min_points_per_cell_) continue;
      const double mdx = a.sx / a.sw, mdy = a.sy / a.sw;  // mean relative to the corner
      // Σ = Σ w [(p − μ)(p − μ)ᵀ + Σᵢ] / Σ w
      const double cxx = std::max(0.0, a.sxx / a.sw - mdx * mdx) + a.cxx / a.sw;
      const double cxy = a.sxy / a.sw - mdx * mdy + a.cxy / a.sw;
      const double cyy = std::max(0.0, a.syy / a.sw - mdy * mdy) + a.cyy / a.sw;
      // Eigen-decomposition of the 2x2 covariance, closed form; floor the small eigenvalue.
      const double tr_half = 0.5 * (cxx + cyy);
      const double disc = std::sqrt(std::max(0.0, 0.25 * (cxx - cyy) * (cxx - cyy) + cxy * cxy));
      double l1 = tr_half + disc, l2 = tr_half - disc;
      l1 = std::max(l1, abs_floor);
      l2 = std::max({l2, eigen_ratio_ * l1, abs_floor});
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
      detail::NdtCell cell;
      cell.mx = a.cx * g + ox + mdx;
      cell.my = a.cy * g + oy + mdy;
      cell.ixx = ia * vx * vx + ic * vy * vy;
      cell.ixy = (ia - ic) * vx * vy;
      cell.iyy = ia * vy * vy + ic * vx * vx;
      cell.weight = a.sw;
      const auto idx = static_cast<std::int32_t>(grid.cells.size());
      grid.cells.push_back(cell);
      if (lookup_ == CellLookup::Neighbours) {
        // Lookup key: the grid vertex nearest the query point; cell (cx, cy) has vertices
        // (cx..cx+1, cy..cy+1), so each vertex lists the 2x2 block of cells around it.
        grid.index.add(a.cx, a.cy, idx);
        grid.index.add(a.cx + 1, a.cy, idx);
        grid.index.add(a.cx, a.cy + 1, idx);
        grid.index.add(a.cx + 1, a.cy + 1, idx);
      } else {
        // Lookup key: the half-size cell the query point falls in; this cell of grid k covers
        // half-cells (2cx + kx .. 2cx + kx + 1, 2cy + ky .. 2cy + ky + 1).
        const std::int32_t hx = 2 * a.cx + kx, hy = 2 * a.cy + ky;
        grid.index.add(hx, hy, idx);
        grid.index.add(hx + 1, hy, idx);
        grid.index.add(hx, hy + 1, idx);
        grid.index.add(hx + 1, hy + 1, idx);
      }
    }
  }
  grid.index.finalize();
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::prepareSource() {
  source_points_.clear();
  if (!input_) return;
  const auto& indices = *this->indices_;
  source_points_.reserve(indices.size());
  const double source_shift = shift_source_ ? power_shift_ : 0.0f;
  for (const auto i : indices) {
    const PointSource& p = (*input_)[i];
    const Eigen::Vector3d cov = detail::pointCovariance(p);
    if (!detail::usable(p.x, p.y, cov)) continue;
    // eq. (2): w = max(p − s, 0) · exp(−½(σx + σy)); s = 0 here with setShiftSourceWeights(false)
    const double w = std::max(0.0, static_cast<double>(detail::pointPower(p)) - source_shift) *
                     detail::expNegative(-0.5 * (std::sqrt(cov.x()) + std::sqrt(cov.z())));
    if (!(w > 0.0) || !std::isfinite(w)) continue;
    source_points_.push_back({p.x, p.y, w});
  }
  // Optional reduction: points in one small voxel become one point at their weighted centroid with
  // their summed weight. The cost Σ wᵢ exp(−½ qᵢᵀΣ⁻¹qᵢ) barely changes while the voxel is small
  // against the cells' spread; evaluation time drops with the point count.
  const double v = source_voxel_size_;  // >= 0, the setter clamps it
  if (v > 0 && source_points_.size() > 1) {
    // Each point's voxel key and the keys' extent, in one pass; points beyond any sensible extent
    // cannot be keyed and are dropped (the rest keep their order).
    std::vector<std::int32_t>& keys = voxel_keys_;
    keys.resize(2 * source_points_.size());
    std::int32_t x0 = std::numeric_limits<std::int32_t>::max(), y0 = x0;
    std::int32_t x1 = std::numeric_limits<std::int32_t>::min(), y1 = x1;
    std::size_t n = 0;
    for (const auto& p : source_points_) {
      const double u = p.x / v, w = p.y / v;
      if (!(std::abs(u) < 1e9 && std::abs(w) < 1e9)) continue;
      const std::int32_t kx = detail::floorToInt(u), ky = detail::floorToInt(w);
      source_points_[n] = p;
      keys[2 * n] = kx;
      keys[2 * n + 1] = ky;
      ++n;
      x0 = std::min(x0, kx);
      x1 = std::max(x1, kx);
      y0 = std::min(y0, ky);
      y1 = std::max(y1, ky);
    }
    source_points_.resize(n);
    // (Σ w x, Σ w y, Σ w), in order of first point; swapped with source_points_ below, so the two
    // buffers take turns and neither is allocated again while scans keep their size.
    std::vector<detail::WeightedPoint2D>& merged = voxel_merged_;
    merged.clear();
    merged.reserve(n);
    auto accumulate = [&](std::int32_t slot, const detail::WeightedPoint2D& p) {
      auto& m = merged[static_cast<std::size_t>(slot)];
      m.x += p.w * p.x;
      m.y += p.w * p.y;
      m.w += p.w;
    };
    const std::int64_t width = std::int64_t(x1) - x0 + 1, height = std::int64_t(y1) - y0 + 1;
    // A compact extent (a scan, a submap): a dense table of voxel slots, filled in far less time than
    // hashing the points takes (at most 64 slots a point beyond 1 MB, and never over 16 MB).
    // Neighbouring points share table rows, where a hash scatters them; both keep first-seen order,
    // so the merged points are the same either way.
    const std::int64_t slots = width * height;
    if (n > 0 && slots <= std::min<std::int64_t>(64 * static_cast<std::int64_t>(n) + (1 << 18), 1 << 22)) {
      voxel_table_.assign(static_cast<std::size_t>(slots), -1);
      for (std::size_t i = 0; i < n; ++i) {
        std::int32_t& slot = voxel_table_[static_cast<std::size_t>(std::int64_t(keys[2 * i] - x0) * height +
                                                                   (keys[2 * i + 1] - y0))];
        if (slot < 0) {
          slot = static_cast<std::int32_t>(merged.size());
          merged.push_back({0, 0, 0});
        }
        accumulate(slot, source_points_[i]);
      }
    } else {
      detail::KeyIndexMap map(n);
      for (std::size_t i = 0; i < n; ++i) {
        bool inserted = false;
        const std::int32_t slot =
            map.findOrInsert(keys[2 * i], keys[2 * i + 1], static_cast<std::int32_t>(merged.size()), inserted);
        if (inserted) merged.push_back({0, 0, 0});
        accumulate(slot, source_points_[i]);
      }
    }
    for (auto& m : merged) {
      m.x /= m.w;
      m.y /= m.w;
    }
    source_points_.swap(merged);
  }
}

template <typename PointSource, typename PointTarget>
double WeightedNDT2D<PointSource, PointTarget>::evaluate(const detail::NdtGrid& grid, const Eigen::Vector3d& x,
                                                         Eigen::Vector3d* gradient, Eigen::Matrix3d* hessian,
                                                         std::size_t* matched, Eigen::Matrix3d* information,
                                                         std::size_t stride) const {
  // Points farther than this (squared Mahalanobis) from a cell contribute < e^-15 of their weight.
  constexpr double kMaxMahalanobis = 30.0;
  const double c = std::cos(x.z()), s = std::sin(x.z());
  const double tx = x.x(), ty = x.y();
  double value = 0;
  double g0 = 0, g1 = 0, g2 = 0;
  double h00 = 0, h01 = 0, h02 = 0, h11 = 0, h12 = 0, h22 = 0;
  double i00 = 0, i01 = 0, i02 = 0, i11 = 0, i12 = 0, i22 = 0;
  std::size_t n_matched = 0;
  for (std::size_t i = 0; i < source_points_.size(); i += stride) {
    const auto& p = source_points_[i];
    const double rx = c * p.x - s * p.y, ry = s * p.x + c * p.y;  // R p
    const double qx = rx + tx, qy = ry + ty;
    const std::int32_t* slots = grid.cellsNear(qx, qy);
    if (!slots) continue;
    const double jx = -ry, jy = rx;  // ∂q/∂yaw
    bool hit = false;
    for (int k = 0; k < 4; ++k) {
      if (slots[k] < 0) continue;
      const detail::NdtCell& cell = grid.cells[static_cast<std::size_t>(slots[k])];
      const double dx = qx - cell.mx, dy = qy - cell.my;
      const double ax = cell.ixx * dx + cell.ixy * dy, ay = cell.ixy * dx + cell.iyy * dy;  // Σ⁻¹ d
      const double m = dx * ax + dy * ay;
      if (m > kMaxMahalanobis) continue;
      hit = true;
      const double e = p.w * detail::expNegative(-0.5 * m);  // m <= 30: argument in [-15, 0]
      value -= e;
      if (!gradient) continue;
      const double a2 = ax * jx + ay * jy;  // dᵀ Σ⁻¹ ∂q/∂yaw
      g0 += e * ax;
      g1 += e * ay;
      g2 += e * a2;
      const double cjx = cell.ixx * jx + cell.ixy * jy, cjy = cell.ixy * jx + cell.iyy * jy;  // Σ⁻¹ ∂q/∂yaw
      if (hessian) {
        // Biber & Straßer (2003): H_kl = e [−(aᵀJ_k)(aᵀJ_l) + J_lᵀΣ⁻¹J_k + aᵀ ∂²q/∂x_k∂x_l],
        // with ∂²q/∂yaw² = −R p and the other second derivatives zero.
        h00 += e * (cell.ixx - ax * ax);
        h01 += e * (cell.ixy - ax * ay);
        h02 += e * (cjx - ax * a2);
        h11 += e * (cell.iyy - ay * ay);
        h12 += e * (cjy - ay * a2);
        h22 += e * (jx * cjx + jy * cjy - a2 * a2 - ax * rx - ay * ry);
      }
      if (information) {
        i00 += e * cell.ixx;
        i01 += e * cell.ixy;
        i02 += e * cjx;
        i11 += e * cell.iyy;
        i12 += e * cjy;
        i22 += e * (jx * cjx + jy * cjy);
      }
    }
    if (hit) ++n_matched;
  }
  if (gradient) *gradient << g0, g1, g2;
  if (hessian) *hessian << h00, h01, h02, h01, h11, h12, h02, h12, h22;
  if (information) *information << i00, i01, i02, i01, i11, i12, i02, i12, i22;
  if (matched) *matched = n_matched;
  return value;
}

template <typename PointSource, typename PointTarget>
void WeightedNDT2D<PointSource, PointTarget>::computeTransformation(PointCloudSource& output, const Matrix4& guess) {
  converged_ = false;
  degenerate_ = false;
  final_num_iterations_ = 0;
  num_matched_points_ = 0;
  final_score_ = 0;
  final_hessian_.setZero();
  pose_covariance_ = Eigen::Matrix3d::Identity() * std::numeric_limits<double>::infinity();

  Pose2 x = toPose2(guess);
  if (!x.allFinite()) {
    PCL_ERROR("[radar_ndt::%s::computeTransformation] the initial guess is not finite\n", reg_name_.c_str());
    x.setZero();
  }
  if (model_stale_) buildTargetModel();
  prepareSource();

  auto finish = [&](const Pose2& pose) {
    final_transformation_ = transformation_ = toMatrix4<float>(pose);
    pcl::transformPointCloud(output, output, final_transformation_);
    if constexpr (pcl::traits::has_field<PointSource, pcl::fields::cov_xx>::value) {
      const Eigen::Matrix2d R = Eigen::Rotation2Dd(pose.z()).toRotationMatrix();
      for (auto& p : output) detail::rotateCovariance(p, R);
    }
    nr_iterations_ = final_num_iterations_;
  };

  if (grids_.empty() || grids_.back().cells.empty() || source_points_.empty()) {
    // Not an error of the call: the data left nothing to match (e.g. Doppler weights that agree
    // with no point, in the source or in the target: the last cycle's weighted submap). hasConverged()
    // and wasDegenerate() report it, as for too few matched points below, without a message a scan.
    PCL_DEBUG("[radar_ndt::%s::computeTransformation] degenerate problem: %zu target cells, %zu weighted source "
              "points\n",
              reg_name_.c_str(), grids_.empty() ? std::size_t(0) : grids_.back().cells.size(), source_points_.size());
    degenerate_ = true;
    finish(x);
    return;
  }

  // Far from the optimum precision does not matter: each stage first iterates on a deterministic
  // 1-in-kSubsample subsample of the source (every k-th point in voxel order, spread over the
  // scan) until its steps fall under 1 cm and 1 mrad, then finishes on all points with the user's
  // epsilons. The fine phase starts close to the optimum and needs few Newton steps.
  constexpr std::size_t kSubsample = 4;
  const bool coarse_phase = source_points_.size() >= 16 * kSubsample;
  bool stage_converged = false;
  // The finest grid's full-resolution phase evaluates, with the information matrix and matched
  // count, every x it moves to (the final x may be a step below the epsilons further on), so the
  // diagnostics below need no extra pass.
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero(), info_n;
  std::size_t matched = 0, matched_n = 0;
  double final_f = 0;
  Eigen::Matrix3d final_H = Eigen::Matrix3d::Zero();
  for (const auto& grid : grids_) {
    const bool finest = &grid == &grids_.back();
    const double max_t = max_step_translation_ > 0 ? max_step_translation_ : 0.5 * grid.resolution;
    int stage_iterations = 0;  // setMaximumIterations bounds both phases of a stage together
    for (int phase = coarse_phase ? 0 : 1; phase < 2; ++phase) {
      const std::size_t stride = phase == 0 ? kSubsample : 1;
      const double eps_t = phase == 0 ? std::max(1e-4, transformation_epsilon_) : transformation_epsilon_;
      const double eps_r = phase == 0 ? std::min(std::cos(1e-3), transformation_rotation_epsilon_)
                                      : transformation_rotation_epsilon_;
      auto isSmall = [&](const Eigen::Vector3d& d) {  // a step below this phase's epsilons
        return d.head<2>().squaredNorm() < eps_t && std::cos(d.z()) >= eps_r;
      };
      const bool diagnose = finest && phase == 1;  // also compute what the diagnostics need
      Eigen::Vector3d g;
      Eigen::Matrix3d H;
      double f = evaluate(grid, x, &g, &H, diagnose ? &matched : nullptr, diagnose ? &info : nullptr, stride);
      stage_converged = false;
      while (stage_iterations < max_iterations_) {
        ++stage_iterations;
        ++final_num_iterations_;
        // Newton direction with a positive definite Hessian: eigenvalues mirrored and floored.
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(H);
        Eigen::Vector3d lambda = es.eigenvalues().cwiseAbs();
        const double lmax = lambda.maxCoeff();
        if (!(lmax > 0) || !std::isfinite(lmax)) break;  // no point matched: nothing to optimise
        for (int i = 0; i < 3; ++i) lambda(i) = std::max(lambda(i), 1e-6 * lmax);
        Eigen::Vector3d step =
            -es.eigenvectors() * (lambda.cwiseInverse().asDiagonal() * (es.eigenvectors().transpose() * g));
        // Limit the step, then backtrack until the score improves enough (Armijo).
        const double tnorm = step.head<2>().norm();
        double scale = 1.0;
        if (tnorm > max_t) scale = max_t / tnorm;
        if (std::abs(step.z()) * scale > max_step_rotation_) scale = max_step_rotation_ / std::abs(step.z());
        step *= scale;
        const double slope = g.dot(step);  // < 0 for a descent direction
        // A step below the epsilons is not tested against the score: the score jumps where points
        // change cells, by more than such a step's predicted decrease, so the line search would
        // only halve it many times over. A Newton step that small is the converged answer and is
        // taken; a backtracked one that small means x is the answer.
        if (isSmall(step)) {
          x += step;
          x.z() = normalizeAngle(x.z());
          stage_converged = true;
          // f, g, H and the diagnostics stay those of the previous x, less than the epsilons away.
          break;
        }
        // The full step usually passes, so it is evaluated with derivatives; shorter trials are
        // value-only and the derivatives are computed once one of them passes.
        double alpha = 1.0;
        bool accepted = false, have_derivatives = false;
        double fn = f;
        Eigen::Vector3d gn;
        Eigen::Matrix3d Hn;
        for (int ls = 0; ls < 12; ++ls) {
          if (ls > 0 && isSmall(alpha * step)) break;
          fn = ls == 0 ? evaluate(grid, x + step, &gn, &Hn, diagnose ? &matched_n : nullptr,
                                  diagnose ? &info_n : nullptr, stride)
                       : evaluate(grid, x + alpha * step, nullptr, nullptr, nullptr, nullptr, stride);
          if (fn <= f + 1e-4 * alpha * slope) {
            accepted = true;
            have_derivatives = ls == 0;
            break;
          }
          alpha *= 0.5;
        }
        const Eigen::Vector3d applied = alpha * step;
        if (!accepted) {
          // No step along a descent direction improves the score: at the optimum to the score's
          // resolution when the step has shrunk below the epsilons or the predicted decrease is
          // negligible, otherwise stuck (not converged). x stays.
          stage_converged = isSmall(applied) || std::abs(slope) < 1e-6 * std::max(1e-12, std::abs(f));
          break;
        }
        // An accepted step is never below the epsilons (those are taken or refused above), so the
        // stage goes on from the new x with its derivatives.
        x += applied;
        x.z() = normalizeAngle(x.z());
        if (have_derivatives) {
          f = fn;
          g = gn;
          H = Hn;
          info = info_n;
          matched = matched_n;
        } else {
          f = evaluate(grid, x, &g, &H, diagnose ? &matched : nullptr, diagnose ? &info : nullptr, stride);
        }
      }
      if (diagnose) {
        final_f = f;
        final_H = H;
      }
    }
  }

  // Final diagnostics on the finest grid, from the loop's last evaluation there.
  final_score_ = -final_f;
  final_hessian_ = final_H;
  num_matched_points_ = matched;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(info);
  const double imax = es.eigenvalues().maxCoeff(), imin = es.eigenvalues().minCoeff();
  if (num_matched_points_ < 3 || !(imax > 0) || !(imin > 1e-9 * imax)) {
    degenerate_ = true;
    PCL_DEBUG("[radar_ndt::%s::computeTransformation] degenerate: %zu matched points, information eigenvalues "
              "%g..%g\n",
              reg_name_.c_str(), num_matched_points_, imin, imax);
  } else {
    pose_covariance_ = info.inverse();
  }
  converged_ = stage_converged && !degenerate_;
  finish(x);
}

}  // namespace radar_ndt
