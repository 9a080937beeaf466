#pragma once
// Newton's method on (x, y, yaw) as WeightedNDT2D runs it: a positive definite Newton direction,
// a step limit, an Armijo line search and a termination criterion on the step, each its own
// piece (as small_gicp splits its optimizer and termination criteria).

#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "radar_ndt/se2.h"

namespace radar_ndt {
namespace detail {

/// Termination: a step is small enough to stop at when its squared translation is below
/// `translation_sq` and the cosine of its rotation at least `rotation_cos` (PCL's two epsilons).
struct StepTolerance {
  double translation_sq;
  double rotation_cos;
  bool isSmall(const Eigen::Vector3d& d) const {
    return d.head<2>().squaredNorm() < translation_sq && std::cos(d.z()) >= rotation_cos;
  }
};

/// Where a Newton step that no line search can improve on still counts as converged: within this
/// much of x (translation m, rotation rad) the Newton model's optimum lies within the score's
/// resolution (points changing cells make the score jump by more than such a step's predicted
/// decrease); further away the search is stuck.
struct StationaryRegion {
  double translation;
  double rotation;
  bool contains(const Eigen::Vector3d& newton_step) const {
    return newton_step.head<2>().norm() <= translation && std::abs(newton_step.z()) <= rotation;
  }
};

/// The largest step the line search starts from: translation (m) and rotation (rad).
struct StepLimit {
  double translation;
  double rotation;
  /// Scales `step` down (direction kept) until both parts are within the limit.
  void apply(Eigen::Vector3d& step) const {
    const double tnorm = step.head<2>().norm();
    double scale = 1.0;
    if (tnorm > translation) scale = translation / tnorm;
    if (std::abs(step.z()) * scale > rotation) scale = rotation / std::abs(step.z());
    step *= scale;
  }
};

/// The Newton direction −H⁻¹g with H made positive definite: its eigenvalues mirrored and
/// floored at 1e-6 of the largest. False when H is zero or not finite (no point matched).
inline bool newtonDirection(const Eigen::Matrix3d& H, const Eigen::Vector3d& g, Eigen::Vector3d* step) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(H);
  Eigen::Vector3d lambda = es.eigenvalues().cwiseAbs();
  const double lmax = lambda.maxCoeff();
  if (!(lmax > 0) || !std::isfinite(lmax)) return false;
  for (int i = 0; i < 3; ++i) lambda(i) = std::max(lambda(i), 1e-6 * lmax);
  *step = -es.eigenvectors() * (lambda.cwiseInverse().asDiagonal() * (es.eigenvectors().transpose() * g));
  return true;
}

/// The optimiser's state at its current x: value, gradient, Hessian, and whatever else the cost
/// computes along with its derivatives (`Extra`, e.g. diagnostics).
template <typename Extra>
struct NewtonState {
  double f = 0;
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  Extra extra{};
};

/// Minimises `cost` from `x` by Newton steps until a step falls below `tolerance` (converged), the
/// line search finds no improvement (converged when the Newton step it started from lies within
/// `stationary`, stuck otherwise), or `*iterations` reaches `max_iterations`; every iteration also
/// counts in `*total`. `cost(x, g, H, extra)` returns the value at x and, when g, H and extra
/// are not null, the derivatives and extras. Returns whether it converged; `state` holds the value
/// and derivatives at the last x it evaluated with derivatives (a step below the tolerance is taken
/// without evaluating it).
template <typename Cost, typename Extra>
bool minimizeNewton(const Cost& cost, Eigen::Vector3d& x, NewtonState<Extra>& state, const StepTolerance& tolerance,
                    const StepLimit& limit, const StationaryRegion& stationary, int max_iterations, int* iterations,
                    int* total) {
  constexpr int kMaxHalvings = 12;
  state.f = cost(x, &state.g, &state.H, &state.extra);
  while (*iterations < max_iterations) {
    ++*iterations;
    ++*total;
    Eigen::Vector3d step;
    if (!newtonDirection(state.H, state.g, &step)) return false;  // no point matched: nothing to optimise
    const bool near_optimum = stationary.contains(step);          // judged on the full Newton step, before the limit
    limit.apply(step);
    const double slope = state.g.dot(step);  // < 0 for a descent direction
    // A step below the tolerance is not tested against the score: the score jumps where points
    // change cells, by more than such a step's predicted decrease, so the line search would only
    // halve it many times over. A Newton step that small is the converged answer and is taken; a
    // backtracked one that small means x is the answer.
    if (tolerance.isSmall(step)) {
      x += step;
      x.z() = normalizeAngle(x.z());
      return true;  // the state stays that of the previous x, less than the tolerance away
    }
    // Armijo backtracking. The full step usually passes, so it is evaluated with derivatives;
    // shorter trials are value-only and the derivatives are computed once one of them passes.
    double alpha = 1.0;
    bool accepted = false, have_derivatives = false;
    NewtonState<Extra> next;
    for (int ls = 0; ls < kMaxHalvings; ++ls) {
      if (ls > 0 && tolerance.isSmall(alpha * step)) break;
      next.f =
          ls == 0 ? cost(x + step, &next.g, &next.H, &next.extra) : cost(x + alpha * step, nullptr, nullptr, nullptr);
      if (next.f <= state.f + 1e-4 * alpha * slope) {
        accepted = true;
        have_derivatives = ls == 0;
        break;
      }
      alpha *= 0.5;
    }
    if (!accepted) {
      // No step along the descent direction improves the score. Converged when the Newton step
      // (from the gradient and Hessian at x, not from how far the search halved it) lies within
      // the stationary region or predicts a negligible decrease: x is the optimum to the score's
      // resolution. Otherwise stuck away from an optimum: not converged. x stays.
      return near_optimum || std::abs(slope) < 1e-6 * std::max(1e-12, std::abs(state.f));
    }
    // An accepted step is never below the tolerance (those are taken or refused above), so the
    // search goes on from the new x with its derivatives.
    x += alpha * step;
    x.z() = normalizeAngle(x.z());
    if (have_derivatives)
      state = next;
    else
      state.f = cost(x, &state.g, &state.H, &state.extra);
  }
  return false;
}

}  // namespace detail
}  // namespace radar_ndt
