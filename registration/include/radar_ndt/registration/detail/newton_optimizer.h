#pragma once
// Newton's method as WeightedNDT2D (on (x, y, yaw)) and WeightedNDT3D (on SE(3)) run it: a
// positive definite Newton direction, a step limit, an Armijo line search and a termination
// criterion on the step, each its own piece (as small_gicp splits its optimizer and termination
// criteria), with every constant in one settings struct (NewtonSettings) filled from the
// matcher's settings. A step is a tangent vector: (x, y, yaw) on SE(2), (translation, rotation
// vector) on SE(3); the overloads below tell its translation and rotation apart and move a pose
// by it.

#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "radar_ndt/registration/weighted_ndt_2d_settings.h"
#include "radar_ndt/se2.h"
#include "radar_ndt/se3.h"

namespace radar_ndt {
namespace detail {

// A step's parts, on SE(2) (x, y, yaw) and on SE(3) (translation, rotation vector).
inline double translationNorm(const Eigen::Vector3d& d) {
  return d.head<2>().norm();
}
inline double translationSquaredNorm(const Eigen::Vector3d& d) {
  return d.head<2>().squaredNorm();
}
inline double rotationAngle(const Eigen::Vector3d& d) {
  return std::abs(d.z());
}
inline double rotationCosine(const Eigen::Vector3d& d) {
  return std::cos(d.z());
}
inline double translationNorm(const Vector6d& d) {
  return d.head<3>().norm();
}
inline double translationSquaredNorm(const Vector6d& d) {
  return d.head<3>().squaredNorm();
}
inline double rotationAngle(const Vector6d& d) {
  return d.tail<3>().norm();
}
inline double rotationCosine(const Vector6d& d) {
  return std::cos(d.tail<3>().norm());
}

// A pose moved by a step: `retract` for a trial, `advance` for an accepted step (on SE(2) the yaw
// is wrapped there; on SE(3) the rotation is re-orthonormalised at every step).
inline Eigen::Vector3d retract(const Eigen::Vector3d& x, const Eigen::Vector3d& d) {
  return x + d;
}
inline void advance(Eigen::Vector3d& x, const Eigen::Vector3d& d) {
  x += d;
  x.z() = normalizeAngle(x.z());
}
inline Pose3 retract(const Pose3& x, const Vector6d& d) {
  return retractSE3(x, d);
}
inline void advance(Pose3& x, const Vector6d& d) {
  x = retractSE3(x, d);
}

/// Termination: a step is small enough to stop at when its squared translation is below
/// `translation_sq` and the cosine of its rotation at least `rotation_cos` (PCL's two epsilons).
struct StepTolerance {
  double translation_sq;
  double rotation_cos;
  template <typename Step>
  bool isSmall(const Step& d) const {
    return translationSquaredNorm(d) < translation_sq && rotationCosine(d) >= rotation_cos;
  }
};

/// Where a Newton step that no line search can improve on still counts as converged: within this
/// much of x (translation m, rotation rad) the Newton model's optimum lies within the score's
/// resolution (points changing cells make the score jump by more than such a step's predicted
/// decrease); further away the search is stuck.
struct StationaryRegion {
  double translation;
  double rotation;
  template <typename Step>
  bool contains(const Step& newton_step) const {
    return translationNorm(newton_step) <= translation && rotationAngle(newton_step) <= rotation;
  }
};

/// The largest step the line search starts from: translation (m) and rotation (rad).
struct StepLimit {
  double translation;
  double rotation;
  /// Scales `step` down (direction kept) until both parts are within the limit.
  template <typename Step>
  void apply(Step& step) const {
    const double tnorm = translationNorm(step), angle = rotationAngle(step);
    double scale = 1.0;
    if (tnorm > translation) scale = translation / tnorm;
    if (angle * scale > rotation) scale = rotation / angle;
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
/// N is taken from `step` alone, so H and g may be any expression of their size.
template <int N>
struct Square {
  using Matrix = Eigen::Matrix<double, N, N>;
  using Vector = Eigen::Matrix<double, N, 1>;
};
template <int N>
inline bool newtonDirection(const typename Square<N>::Matrix& H, const typename Square<N>::Vector& g,
                            Eigen::Matrix<double, N, 1>* step, double floor = LineSearchDefaults::eigenvalue_floor) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> es(H);
  Eigen::Matrix<double, N, 1> lambda = es.eigenvalues().cwiseAbs();
  const double lmax = lambda.maxCoeff();
  if (!(lmax > 0) || !std::isfinite(lmax)) return false;
  for (int i = 0; i < N; ++i) lambda(i) = std::max(lambda(i), floor * lmax);
  *step = -es.eigenvectors() * (lambda.cwiseInverse().asDiagonal() * (es.eigenvectors().transpose() * g));
  return true;
}

/// The optimiser's state at its current x: value, gradient, Hessian, and whatever else the cost
/// computes along with its derivatives (`Extra`, e.g. diagnostics); N = 3 on SE(2), 6 on SE(3).
template <typename Extra, int N = 3>
struct NewtonState {
  using Step = Eigen::Matrix<double, N, 1>;
  double f = 0;
  Step g = Step::Zero();
  Eigen::Matrix<double, N, N> H = Eigen::Matrix<double, N, N>::Zero();
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
template <typename Cost, typename Pose, typename Extra, int N>
double lineSearch(const Cost& cost, const Pose& x, const NewtonState<Extra, N>& state,
                  const typename NewtonState<Extra, N>::Step& step, double slope, const NewtonSettings& s,
                  NewtonState<Extra, N>& next, bool* with_derivatives) {
  using Step = typename NewtonState<Extra, N>::Step;
  double alpha = 1.0;
  for (int ls = 0; ls < s.max_halvings; ++ls) {
    if (ls > 0 && s.tolerance.isSmall(Step(alpha * step))) break;
    next.f = ls == 0 ? cost(retract(x, step), &next.g, &next.H, &next.extra)
                     : cost(retract(x, Step(alpha * step)), nullptr, nullptr, nullptr);
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
template <typename Cost, typename Pose, typename Extra, int N>
NewtonRun minimizeNewton(const Cost& cost, Pose& x, NewtonState<Extra, N>& state, const NewtonSettings& s) {
  using Step = typename NewtonState<Extra, N>::Step;
  NewtonRun run;
  state.f = cost(x, &state.g, &state.H, &state.extra);
  while (run.iterations < s.max_iterations) {
    ++run.iterations;
    Step step;
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
      advance(x, step);
      run.outcome = NewtonOutcome::Converged;  // the state stays that of the previous x, under the tolerance away
      return run;
    }
    NewtonState<Extra, N> next;
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
    advance(x, Step(alpha * step));
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
