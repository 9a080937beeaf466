#pragma once
// The cost WeightedNDT3D minimises: the negative weighted NDT score of the paper's eq. (2) in 3D,
// −Σ wᵢ exp(−½ dᵀΣ⁻¹d) with d = R pᵢ + t − μ, with its analytic gradient and Hessian on SE(3)
// (Magnusson 2009's derivation, in the chart (R, t) → (exp(ω) R, t + v)) and the
// point-to-distribution information the pose covariance comes from.
//
// With r = R p: ∂q/∂v = I, ∂q/∂ω = −[r]×, ∂²q/∂ωₐ∂ω_b = ½(eₐ r_b + e_b rₐ) − δₐ_b r, the other
// second derivatives zero. For one point and cell, a = Σ⁻¹d and e its weighted Gaussian score:
// gradient e Jᵀa = e (a, r × a); Hessian e [JᵀΣ⁻¹J − (Jᵀa)(Jᵀa)ᵀ + aᵀ∂²q] (as Biber & Straßer's
// in 2D).

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "radar_ndt/registration/detail/fast_exp.h"
#include "radar_ndt/registration/detail/ndt_grid_3d.h"
#include "radar_ndt/se3.h"

namespace radar_ndt {
namespace detail {

/// One point's terms summed over the cells it is scored against (in slot order): the score, Σ e a,
/// Σ e (Σ⁻¹ − a aᵀ) and Σ e Σ⁻¹, as asked.
struct PointTerms {
  double score = 0;
  bool hit = false;
  Eigen::Vector3d ga = Eigen::Vector3d::Zero();
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
};

inline PointTerms pointTerms(const NdtGrid3D& grid, const CellBlock& block, const Eigen::Vector3d& q, double w,
                             bool gradient, bool hessian, bool information) {
  // Points farther than this (squared Mahalanobis) from a cell contribute < e^-15 of their weight.
  constexpr double kMaxMahalanobis = 30.0;
  PointTerms t;
  for (const std::int32_t slot : block.slots) {
    if (slot < 0) break;  // a block's cells fill its slots from the front
    const NdtCell3D& cell = grid.cells[static_cast<std::size_t>(slot)];
    const Eigen::Vector3d d = q - cell.mean;
    const Eigen::Vector3d a = cell.inverse * d;  // Σ⁻¹ d
    const double m = d.dot(a);
    if (m > kMaxMahalanobis) continue;
    t.hit = true;
    const double e = w * expNegative(-0.5 * m);  // m <= 30: argument in [-15, 0]
    t.score += e;
    if (!gradient) continue;
    t.ga += e * a;
    if (hessian) t.M.noalias() += e * (cell.inverse - a * a.transpose());
    if (information) t.A.noalias() += e * cell.inverse;
  }
  return t;
}

/// Value, gradient and Hessian of the negative score at pose x on one grid, and optionally the
/// matched point count and the information Σᵢ wᵢ eᵢ Jᵢᵀ Σ⁻¹ Jᵢ. Deterministic: terms are summed in
/// source-point order. `stride` > 1 uses every stride-th point.
///
/// J = [I, Jω] is the same for every cell a point is scored against, and b = Jωᵀa, so a point's
/// terms are summed over its cells first (pointTerms: M = Σ e (Σ⁻¹ − a aᵀ), m = Σ e a, and Σ e Σ⁻¹
/// for the information), and J applied once a point: H_tt += M, H_tω += M Jω,
/// H_ωω += Jωᵀ M Jω + S(m), S(m) = ½(m rᵀ + r mᵀ) − (mᵀr) I.
inline double ndtCost3D(const NdtGrid3D& grid, const std::vector<WeightedPoint3D>& points, const Pose3& x,
                        Vector6d* gradient, Matrix6d* hessian, std::size_t* matched = nullptr,
                        Matrix6d* information = nullptr, std::size_t stride = 1) {
  const Eigen::Matrix3d R = x.linear();
  const Eigen::Vector3d t = x.translation();
  double value = 0;
  Vector6d g = Vector6d::Zero();
  Matrix6d H = Matrix6d::Zero(), I = Matrix6d::Zero();
  std::size_t hits = 0;
  for (std::size_t i = 0; i < points.size(); i += stride) {
    const Eigen::Vector3d r = R * points[i].p;
    const Eigen::Vector3d q = r + t;
    const CellBlock* block = grid.cellsNear(q);
    if (!block) continue;
    const PointTerms p = pointTerms(grid, *block, q, points[i].w, gradient, hessian, information);
    if (!p.hit) continue;
    ++hits;
    value -= p.score;
    if (!gradient) continue;
    g.head<3>() += p.ga;
    g.tail<3>() += r.cross(p.ga);         // Jωᵀ Σ e a
    const Eigen::Matrix3d Jw = -skew(r);  // ∂q/∂ω
    if (hessian) {
      const Eigen::Matrix3d MJ = p.M * Jw;
      Eigen::Matrix3d S = 0.5 * (p.ga * r.transpose() + r * p.ga.transpose());  // Σ e aᵀ ∂²q/∂ω²
      S.diagonal().array() -= p.ga.dot(r);
      H.topLeftCorner<3, 3>() += p.M;
      H.topRightCorner<3, 3>() += MJ;
      H.bottomRightCorner<3, 3>() += Jw.transpose() * MJ + S;
    }
    if (information) {
      const Eigen::Matrix3d AJ = p.A * Jw;
      I.topLeftCorner<3, 3>() += p.A;
      I.topRightCorner<3, 3>() += AJ;
      I.bottomRightCorner<3, 3>() += Jw.transpose() * AJ;
    }
  }
  if (gradient) *gradient = g;
  if (hessian) {
    H.bottomLeftCorner<3, 3>() = H.topRightCorner<3, 3>().transpose();
    *hessian = H;
  }
  if (information) {
    I.bottomLeftCorner<3, 3>() = I.topRightCorner<3, 3>().transpose();
    *information = I;
  }
  if (matched) *matched = hits;
  return value;
}

}  // namespace detail
}  // namespace radar_ndt
