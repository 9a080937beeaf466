#pragma once
// The cost WeightedNDT2D minimises: the negative weighted NDT score of the paper's eq. (2),
// −Σ wᵢ exp(−½ qᵀΣ⁻¹q) with q = T(x)pᵢ − μ, with its analytic gradient and Hessian on SE(2)
// (Biber & Straßer 2003) and the point-to-distribution information the pose covariance comes from.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "radar_ndt/registration/detail/fast_exp.h"
#include "radar_ndt/registration/detail/ndt_grid.h"
#include "radar_ndt/registration/detail/source_points.h"

namespace radar_ndt {
namespace detail {

/// The cost's running sums, added in source-point order: value, gradient, Hessian (upper
/// triangle), information (upper triangle) and the matched points.
struct NdtSums {
  double value = 0;
  double g0 = 0, g1 = 0, g2 = 0;
  double h00 = 0, h01 = 0, h02 = 0, h11 = 0, h12 = 0, h22 = 0;
  double i00 = 0, i01 = 0, i02 = 0, i11 = 0, i12 = 0, i22 = 0;
  std::size_t matched = 0;
};

/// Hands the sums out: gradient, symmetric Hessian and information, matched count (each when
/// asked for); returns the cost's value.
inline double writeSums(const NdtSums& sum, Eigen::Vector3d* gradient, Eigen::Matrix3d* hessian, std::size_t* matched,
                        Eigen::Matrix3d* information) {
  if (gradient) *gradient << sum.g0, sum.g1, sum.g2;
  if (hessian) *hessian << sum.h00, sum.h01, sum.h02, sum.h01, sum.h11, sum.h12, sum.h02, sum.h12, sum.h22;
  if (information) *information << sum.i00, sum.i01, sum.i02, sum.i01, sum.i11, sum.i12, sum.i02, sum.i12, sum.i22;
  if (matched) *matched = sum.matched;
  return sum.value;
}

/// Adds one point-to-cell term's Hessian and information to `s`: e its weighted Gaussian score,
/// (ax, ay) = Σ⁻¹ d, a2 = dᵀ Σ⁻¹ ∂q/∂yaw, (jx, jy) = ∂q/∂yaw, (rx, ry) = R p.
inline void addSecondOrder(NdtSums& s, double e, const NdtCell& cell, double ax, double ay, double a2, double jx,
                           double jy, double rx, double ry, bool hessian, bool information) {
  const double cjx = cell.ixx * jx + cell.ixy * jy, cjy = cell.ixy * jx + cell.iyy * jy;  // Σ⁻¹ ∂q/∂yaw
  if (hessian) {
    // Biber & Straßer (2003): H_kl = e [−(aᵀJ_k)(aᵀJ_l) + J_lᵀΣ⁻¹J_k + aᵀ ∂²q/∂x_k∂x_l],
    // with ∂²q/∂yaw² = −R p and the other second derivatives zero.
    s.h00 += e * (cell.ixx - ax * ax);
    s.h01 += e * (cell.ixy - ax * ay);
    s.h02 += e * (cjx - ax * a2);
    s.h11 += e * (cell.iyy - ay * ay);
    s.h12 += e * (cjy - ay * a2);
    s.h22 += e * (jx * cjx + jy * cjy - a2 * a2 - ax * rx - ay * ry);
  }
  if (information) {
    s.i00 += e * cell.ixx;
    s.i01 += e * cell.ixy;
    s.i02 += e * cjx;
    s.i11 += e * cell.iyy;
    s.i12 += e * cjy;
    s.i22 += e * (jx * cjx + jy * cjy);
  }
}

/// Value, gradient and Hessian of the negative score at pose x = (tx, ty, yaw) on one grid, and
/// optionally the matched point count and the information Σᵢ wᵢ eᵢ Jᵢᵀ Σ⁻¹ Jᵢ. Deterministic: terms
/// are summed in source-point order. `stride` > 1 uses every stride-th point.
inline double ndtCost(const NdtGrid& grid, const std::vector<WeightedPoint2D>& points, const Eigen::Vector3d& x,
                      Eigen::Vector3d* gradient, Eigen::Matrix3d* hessian, std::size_t* matched = nullptr,
                      Eigen::Matrix3d* information = nullptr, std::size_t stride = 1) {
  // Points farther than this (squared Mahalanobis) from a cell contribute < e^-15 of their weight.
  constexpr double kMaxMahalanobis = 30.0;
  const double c = std::cos(x.z()), s = std::sin(x.z());
  const double tx = x.x(), ty = x.y();
  NdtSums sum;
  for (std::size_t i = 0; i < points.size(); i += stride) {
    const auto& p = points[i];
    const double rx = c * p.x - s * p.y, ry = s * p.x + c * p.y;  // R p
    const double qx = rx + tx, qy = ry + ty;
    const std::int32_t* slots = grid.cellsNear(qx, qy);
    if (!slots) continue;
    const double jx = -ry, jy = rx;  // ∂q/∂yaw
    bool hit = false;
    for (int k = 0; k < 4; ++k) {
      if (slots[k] < 0) continue;
      const NdtCell& cell = grid.cells[static_cast<std::size_t>(slots[k])];
      const double dx = qx - cell.mx, dy = qy - cell.my;
      const double ax = cell.ixx * dx + cell.ixy * dy, ay = cell.ixy * dx + cell.iyy * dy;  // Σ⁻¹ d
      const double m = dx * ax + dy * ay;
      if (m > kMaxMahalanobis) continue;
      hit = true;
      const double e = p.w * expNegative(-0.5 * m);  // m <= 30: argument in [-15, 0]
      sum.value -= e;
      if (!gradient) continue;
      const double a2 = ax * jx + ay * jy;  // dᵀ Σ⁻¹ ∂q/∂yaw
      sum.g0 += e * ax;
      sum.g1 += e * ay;
      sum.g2 += e * a2;
      if (hessian || information) addSecondOrder(sum, e, cell, ax, ay, a2, jx, jy, rx, ry, hessian, information);
    }
    if (hit) ++sum.matched;
  }
  return writeSums(sum, gradient, hessian, matched, information);
}

}  // namespace detail
}  // namespace radar_ndt
