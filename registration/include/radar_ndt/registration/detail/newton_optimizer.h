#pragma once
// Newton's method on (x, y, yaw) as WeightedNDT2D runs it: a positive definite Newton direction,
// a step limit, an Armijo line search and a termination criterion on the step, each its own
// piece (as small_gicp splits its optimizer and termination criteria), with every constant in one
// settings struct (NewtonSettings) filled from WeightedNDT2DSettings.

#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "radar_ndt/registration/weighted_ndt_2d_settings.h"
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

/// Everything one minimisation runs with.
struct NewtonSettings {
  StepTolerance tolerance;
  StepLimit limit;
  StationaryRegion stationary;
  int max_iterations = 35;
  /// The Hessian's eigenvalues are mirrored and floored at this fraction of the largest.
  double eigenvalue_floor = LineSearchDefaults::eigenvalue_floor;
  /// Armijo's sufficient-decrease factor: a trial step passes when it lowers the cost by at least
  /// this fraction of the decrease the gradient predicts.
  double armijo = LineSearchDefaults::armijo;
  /// Trial steps of the line search: the full step, then halved up to this many times less one.
  int max_halvings = LineSearchDefaults::max_halvings;
  /// A failed line search whose predicted decrease is below this fraction of the cost is at the
  /// optimum whatever the Newton step's length.
  double negligible_decrease = LineSearchDefaults::negligible_decrease;
};

/// Why a minimisation stopped.
enum class NewtonOutcome {
  Converged,       ///< a step below the tolerance, or a failed line search inside the stationary region
  Stuck,           ///< the line search found no improvement away from an optimum
  IterationLimit,  ///< max_iterations reached
  NoDirection,     ///< the Hessian is zero or not finite: no point matched
};

/// The Newton direction −H⁻¹g with H made positive definite: its eigenvalues mirrored and
/// floored at `floor` times the largest. False when H is zero or not finite (no point matched).
inline bool newtonDirection(const Eigen::Matrix3d& H, const Eigen::Vector3d& g, Eigen::Vector3d* step,
                            double floor = LineSearchDefaults::eigenvalue_floor) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(H);
  Eigen::Vector3d lambda = es.eigenvalues().cwiseAbs();
  const double lmax = lambda.maxCoeff();
  if (!(lmax > 0) || !std::isfinite(lmax)) return false;
  for (int i = 0; i < 3; ++i) lambda(i) = std::max(lambda(i), floor * lmax);
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

/// What one minimisation ends with: why it stopped and the Newton iterations it took.
struct NewtonRun {
  NewtonOutcome outcome = NewtonOutcome::IterationLimit;
  int iterations = 0;
  bool converged() const { return outcome == NewtonOutcome::Converged; }
};

/// The Armijo backtracking search along `step` from the state at x: the accepted fraction of the
/// step (0 when none passed). The full step usually passes, so it is evaluated with derivatives
/// (into `next`, `*with_derivatives` set); shorter trials are value-only.
template <typename Cost, typename Extra>
double lineSearch(const Cost& cost, const Eigen::Vector3d& x, const NewtonState<Extra>& state,
                  const Eigen::Vector3d& step, double slope, const NewtonSettings& s, NewtonState<Extra>& next,
                  bool* with_derivatives) {
  double alpha = 1.0;
  for (int ls = 0; ls < s.max_halvings; ++ls) {
    if (ls > 0 && s.tolerance.isSmall(alpha * step)) break;
    next.f =
        ls == 0 ? cost(x + step, &next.g, &next.H, &next.extra) : cost(x + alpha * step, nullptr, nullptr, nullptr);
    if (next.f <= state.f + s.armijo * alpha * slope) {
      *with_derivatives = ls == 0;
      return alpha;
    }
    alpha *= 0.5;
  }
  return 0.0;
}

/// Minimises `cost` from `x` by Newton steps until a step falls below the tolerance (converged),
/// the line search finds no improvement (converged when the Newton step it started from lies
/// within the stationary region, stuck otherwise), or max_iterations is reached.
/// `cost(x, g, H, extra)` returns the value at x and, when g, H and extra are not null, the
/// derivatives and extras. `state` ends holding the value and derivatives at the last x evaluated
/// with derivatives (a step below the tolerance is taken without evaluating it); with no iteration
/// left it is still evaluated at x.
template <typename Cost, typename Extra>
NewtonRun minimizeNewton(const Cost& cost, Eigen::Vector3d& x, NewtonState<Extra>& state, const NewtonSettings& s) {
  NewtonRun run;
  state.f = cost(x, &state.g, &state.H, &state.extra);
  while (run.iterations < s.max_iterations) {
    ++run.iterations;
    Eigen::Vector3d step;
    if (!newtonDirection(state.H, state.g, &step, s.eigenvalue_floor)) {
      run.outcome = NewtonOutcome::NoDirection;  // no point matched: nothing to optimise
      return run;
    }
    const bool near_optimum = s.stationary.contains(step);  // judged on the full Newton step, before the limit
    s.limit.apply(step);
    const double slope = state.g.dot(step);  // < 0 for a descent direction
    // A step below the tolerance is not tested against the score: the score jumps where points
    // change cells, by more than such a step's predicted decrease, so the line search would only
    // halve it many times over. A Newton step that small is the converged answer and is taken; a
    // backtracked one that small means x is the answer.
    if (s.tolerance.isSmall(step)) {
      x += step;
      x.z() = normalizeAngle(x.z());
      run.outcome = NewtonOutcome::Converged;  // the state stays that of the previous x, under the tolerance away
      return run;
    }
    NewtonState<Extra> next;
    bool with_derivatives = false;
    const double alpha = lineSearch(cost, x, state, step, slope, s, next, &with_derivatives);
    if (alpha == 0.0) {
      // No step along the descent direction improves the score. Converged when the Newton step
      // (from the gradient and Hessian at x, not from how far the search halved it) lies within
      // the stationary region or predicts a negligible decrease: x is the optimum to the score's
      // resolution. Otherwise stuck away from an optimum: not converged. x stays.
      const bool at_optimum =
          near_optimum || std::abs(slope) < s.negligible_decrease * std::max(1e-12, std::abs(state.f));
      run.outcome = at_optimum ? NewtonOutcome::Converged : NewtonOutcome::Stuck;
      return run;
    }
    // An accepted step is never below the tolerance (those are taken or refused above), so the
    // search goes on from the new x with its derivatives.
    x += alpha * step;
    x.z() = normalizeAngle(x.z());
    if (with_derivatives)
      state = next;
    else
      state.f = cost(x, &state.g, &state.H, &state.extra);
  }
  run.outcome = NewtonOutcome::IterationLimit;
  return run;
}

}  // namespace detail
}  // namespace radar_ndt
