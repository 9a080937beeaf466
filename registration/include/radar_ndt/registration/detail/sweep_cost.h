#pragma once
// The cost of detail/ndt_cost.h with the source sweep's own motion inside it (beyond the paper;
// docs/matcher.md, "The sweep's motion inside the match"). A scanning radar's sweep takes as long as
// the step between two scans, so the source's points are seen from poses along the vehicle's
// motion, not from one. Each source point carries its time offset τ after the sweep's reference
// time; at constant body velocity the pose it was seen from is m^α, α = τ / Δt, where m is the
// motion over the step from the previous scan's reference time (at the known pose P in the
// target's frame) to the source's, Δt apart. With the source pose x = (t, θ), m = P⁻¹x, so the
// estimated motion and the de-skew of the source are one unknown:
//
//   q = x ⊕ m^α ⊕ p = R(θ + αφ) p + α R(βφ) u + t,   φ = θ − θ_P,  u = t − t_P,  β = (1 + α) / 2.
//
// m^α's translation is α·V(αφ)V(φ)⁻¹ times m's, and V(φ) = sinc(φ/2) R(φ/2), so it is the chord
// α R(βφ − φ) R(−θ_P) u up to sinc(αφ/2) / sinc(φ/2), which differs from 1 by less than φ²/24 (a
// thousandth at a sweep's 8°); that ratio is left out.

#include <cmath>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "radar_ndt/registration/detail/fast_exp.h"
#include "radar_ndt/registration/detail/ndt_cost.h"
#include "radar_ndt/registration/detail/ndt_grid.h"
#include "radar_ndt/registration/detail/source_points.h"

namespace radar_ndt {
namespace detail {

/// The step a source sweep is placed with: Δt (s) from the previous scan's reference time to the
/// source's, and P, the previous scan's reference pose (x, y, yaw) in the target's frame.
struct SweepStep {
  double dt = 0;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
};

/// cos and sin of an angle; within a sweep the angles are small (|a| ≤ 0.5), where a Taylor
/// polynomial is exact to 1e-9 and far cheaper than the library's, which serves the rest.
inline void smallRotation(double a, double& c, double& s) {
  if (std::abs(a) > 0.5) {
    c = std::cos(a);
    s = std::sin(a);
    return;
  }
  const double a2 = a * a;
  c = 1.0 - a2 / 2.0 * (1.0 - a2 / 12.0 * (1.0 - a2 / 30.0 * (1.0 - a2 / 56.0 * (1.0 - a2 / 90.0))));
  s = a * (1.0 - a2 / 6.0 * (1.0 - a2 / 20.0 * (1.0 - a2 / 42.0 * (1.0 - a2 / 72.0 * (1.0 - a2 / 110.0)))));
}

/// One source point placed by x ⊕ m^α: q, the Jacobian's columns ∂q/∂tx, ∂q/∂ty, ∂q/∂θ and the
/// non-zero second derivatives ∂²q/∂tx∂θ, ∂²q/∂ty∂θ, ∂²q/∂θ².
struct SweepPlacement {
  double qx, qy;
  double j0x, j0y, j1x, j1y, j2x, j2y;
  double h02x, h02y, h12x, h12y, h22x, h22y;
};

/// The placement at pose x of a point (px, py) seen α of a step after the source's reference time.
/// c, s: cos and sin of θ; φ = θ − θ_P; (ux, uy) = t − t_P.
inline SweepPlacement placeInSweep(double px, double py, double alpha, double c, double s, double tx, double ty,
                                   double phi, double ux, double uy) {
  SweepPlacement o;
  double ca, sa, cb, sb;
  const double beta = 0.5 * (1.0 + alpha);
  smallRotation(alpha * phi, ca, sa);
  smallRotation(beta * phi, cb, sb);
  const double ax = ca * px - sa * py, ay = sa * px + ca * py;  // R(αφ) p
  const double rx = c * ax - s * ay, ry = s * ax + c * ay;      // r = R(θ + αφ) p
  const double wx = cb * ux - sb * uy, wy = sb * ux + cb * uy;  // w = R(βφ) u
  o.qx = rx + alpha * wx + tx;
  o.qy = ry + alpha * wy + ty;
  // ∂q/∂t = I + α R(βφ)
  o.j0x = 1.0 + alpha * cb;
  o.j0y = alpha * sb;
  o.j1x = -alpha * sb;
  o.j1y = 1.0 + alpha * cb;
  // ∂q/∂θ = (1 + α) J r + αβ J w, J the rotation by +90°
  const double k1 = 1.0 + alpha, k2 = alpha * beta;
  o.j2x = -k1 * ry - k2 * wy;
  o.j2y = k1 * rx + k2 * wx;
  // ∂²q/∂t∂θ = αβ J R(βφ); ∂²q/∂θ² = −(1 + α)² r − αβ² w
  o.h02x = -k2 * sb;
  o.h02y = k2 * cb;
  o.h12x = -k2 * cb;
  o.h12y = -k2 * sb;
  o.h22x = -k1 * k1 * rx - k2 * beta * wx;
  o.h22y = -k1 * k1 * ry - k2 * beta * wy;
  return o;
}

/// Adds one point-to-cell term of the swept placement `q` to `s`: e its weighted Gaussian score,
/// (ax, ay) = Σ⁻¹ d. H_kl = e [J_kᵀΣ⁻¹J_l − (aᵀJ_k)(aᵀJ_l) + aᵀ ∂²q/∂x_k∂x_l] (Biber & Straßer 2003,
/// with the Jacobian no longer the identity in translation).
inline void addSweepTerm(NdtSums& s, double e, const NdtCell& cell, double ax, double ay, const SweepPlacement& q,
                         bool hessian, bool information) {
  const double g0 = ax * q.j0x + ay * q.j0y, g1 = ax * q.j1x + ay * q.j1y, g2 = ax * q.j2x + ay * q.j2y;  // aᵀJ_k
  s.g0 += e * g0;
  s.g1 += e * g1;
  s.g2 += e * g2;
  if (!hessian && !information) return;
  // Σ⁻¹ J_k
  const double c0x = cell.ixx * q.j0x + cell.ixy * q.j0y, c0y = cell.ixy * q.j0x + cell.iyy * q.j0y;
  const double c1x = cell.ixx * q.j1x + cell.ixy * q.j1y, c1y = cell.ixy * q.j1x + cell.iyy * q.j1y;
  const double c2x = cell.ixx * q.j2x + cell.ixy * q.j2y, c2y = cell.ixy * q.j2x + cell.iyy * q.j2y;
  const double i00 = q.j0x * c0x + q.j0y * c0y, i01 = q.j0x * c1x + q.j0y * c1y, i02 = q.j0x * c2x + q.j0y * c2y;
  const double i11 = q.j1x * c1x + q.j1y * c1y, i12 = q.j1x * c2x + q.j1y * c2y, i22 = q.j2x * c2x + q.j2y * c2y;
  if (hessian) {
    s.h00 += e * (i00 - g0 * g0);
    s.h01 += e * (i01 - g0 * g1);
    s.h02 += e * (i02 - g0 * g2 + ax * q.h02x + ay * q.h02y);
    s.h11 += e * (i11 - g1 * g1);
    s.h12 += e * (i12 - g1 * g2 + ax * q.h12x + ay * q.h12y);
    s.h22 += e * (i22 - g2 * g2 + ax * q.h22x + ay * q.h22y);
  }
  if (information) {
    s.i00 += e * i00;
    s.i01 += e * i01;
    s.i02 += e * i02;
    s.i11 += e * i11;
    s.i12 += e * i12;
    s.i22 += e * i22;
  }
}

/// ndtCost with each source point placed by x ⊕ m^α (α = its time offset / step.dt) instead of x.
inline double ndtSweepCost(const NdtGrid& grid, const std::vector<WeightedPoint2D>& points, const SweepStep& step,
                           const Eigen::Vector3d& x, Eigen::Vector3d* gradient, Eigen::Matrix3d* hessian,
                           std::size_t* matched = nullptr, Eigen::Matrix3d* information = nullptr,
                           std::size_t stride = 1) {
  constexpr double kMaxMahalanobis = 30.0;  // as ndtCost
  const double c = std::cos(x.z()), s = std::sin(x.z());
  const double phi = x.z() - step.previous.z();
  const double ux = x.x() - step.previous.x(), uy = x.y() - step.previous.y();
  const double inv_dt = 1.0 / step.dt;
  NdtSums sum;
  for (std::size_t i = 0; i < points.size(); i += stride) {
    const auto& p = points[i];
    const SweepPlacement q = placeInSweep(p.x, p.y, p.t * inv_dt, c, s, x.x(), x.y(), phi, ux, uy);
    const std::int32_t* slots = grid.cellsNear(q.qx, q.qy);
    if (!slots) continue;
    bool hit = false;
    for (int k = 0; k < 4; ++k) {
      if (slots[k] < 0) continue;
      const NdtCell& cell = grid.cells[static_cast<std::size_t>(slots[k])];
      const double dx = q.qx - cell.mx, dy = q.qy - cell.my;
      const double ax = cell.ixx * dx + cell.ixy * dy, ay = cell.ixy * dx + cell.iyy * dy;  // Σ⁻¹ d
      const double m = dx * ax + dy * ay;
      if (m > kMaxMahalanobis) continue;
      hit = true;
      const double e = p.w * expNegative(-0.5 * m);
      sum.value -= e;
      if (gradient) addSweepTerm(sum, e, cell, ax, ay, q, hessian != nullptr, information != nullptr);
    }
    if (hit) ++sum.matched;
  }
  return writeSums(sum, gradient, hessian, matched, information);
}

}  // namespace detail
}  // namespace radar_ndt
