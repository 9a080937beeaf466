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
  double value = 0;
  double g0 = 0, g1 = 0, g2 = 0;
  double h00 = 0, h01 = 0, h02 = 0, h11 = 0, h12 = 0, h22 = 0;
  double i00 = 0, i01 = 0, i02 = 0, i11 = 0, i12 = 0, i22 = 0;
  std::size_t n_matched = 0;
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

}  // namespace detail
}  // namespace radar_ndt
