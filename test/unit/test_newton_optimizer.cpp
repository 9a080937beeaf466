// detail/newton_optimizer.h: the Newton direction, the step limit and tolerance, the line search
// and why a minimisation stops, on constructed costs whose answers are known.
#include <gtest/gtest.h>

#include <cmath>

#include "radar_ndt/registration/detail/newton_optimizer.h"

using namespace radar_ndt;
using namespace radar_ndt::detail;

namespace {

NewtonSettings settingsFor(double cell) {
  NewtonSettings s;
  s.tolerance = {1e-6, std::cos(1e-4)};
  s.limit = {0.5 * cell, 0.2};
  s.stationary = {0.05 * cell, 0.01};
  return s;
}

/// A cost whose gradient and Hessian describe a bowl with its minimum at `centre`, but whose value
/// rises by 1e3 in every direction out of x = 0 up to `reach` from it: the Newton step points at
/// the minimum, and every step the line search tries along it (down to the epsilons) scores worse,
/// as at a cell boundary or a spurious ridge of the score.
struct TrapCost {
  Eigen::Vector3d centre;
  double reach;
  double operator()(const Eigen::Vector3d& x, Eigen::Vector3d* g, Eigen::Matrix3d* H, int*) const {
    const Eigen::Vector3d d = x - centre;
    if (g) *g = 2.0 * d;
    if (H) *H = 2.0 * Eigen::Matrix3d::Identity();
    const double moved = x.norm();
    return d.squaredNorm() + (moved > 0 && moved <= reach ? 1e3 : 0.0);
  }
};

/// An anisotropic bowl (x² + 10 y² + 100 yaw², centred at `centre`), counting its evaluations.
struct Bowl {
  Eigen::Vector3d centre;
  mutable int evaluations = 0;
  double operator()(const Eigen::Vector3d& x, Eigen::Vector3d* g, Eigen::Matrix3d* H, int*) const {
    ++evaluations;
    const Eigen::Vector3d w(1.0, 10.0, 100.0);
    const Eigen::Vector3d d = x - centre;
    if (g) *g = 2.0 * w.cwiseProduct(d);
    if (H) *H = 2.0 * w.asDiagonal().toDenseMatrix();
    return d.cwiseProduct(d).dot(w);
  }
};

}  // namespace

TEST(NewtonOptimizer, AFailedLineSearchIsConvergedOnlyNearTheNewtonOptimum) {
  // Away from the optimum (its Newton step 0.5 m, beyond 5 % of a 3 m cell): stuck, not converged,
  // and x stays where it was, however far the line search halved the step.
  const NewtonSettings s = settingsFor(3.0);
  {
    TrapCost cost{Eigen::Vector3d(0.5, 0.0, 0.0), 10.0};
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    NewtonState<int> state;
    const NewtonRun run = minimizeNewton(cost, x, state, s);
    EXPECT_EQ(run.outcome, NewtonOutcome::Stuck);
    EXPECT_FALSE(run.converged());
    EXPECT_EQ(x, Eigen::Vector3d::Zero());
  }
  // Near it (a 2 cm Newton step, as where points change cells at the optimum): converged.
  {
    TrapCost cost{Eigen::Vector3d(0.02, 0.0, 0.001), 10.0};
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    NewtonState<int> state;
    EXPECT_EQ(minimizeNewton(cost, x, state, s).outcome, NewtonOutcome::Converged);
  }
  // A plain bowl is converged, at its minimum.
  {
    TrapCost cost{Eigen::Vector3d(0.7, -0.3, 0.05), 0.0};
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    NewtonState<int> state;
    EXPECT_TRUE(minimizeNewton(cost, x, state, s).converged());
    EXPECT_NEAR((x - cost.centre).norm(), 0.0, 1e-6);
  }
}

TEST(NewtonOptimizer, StepsAreLimitedSoAFarMinimumTakesSeveralIterations) {
  // A bowl 4 m away with a 0.5 m step limit: Newton's exact step is cut to 0.5 m each time, so
  // reaching it takes eight limited steps and a last one inside the tolerance.
  NewtonSettings s = settingsFor(1.0);
  Bowl cost{Eigen::Vector3d(4.0, 0.0, 0.0)};
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  NewtonState<int> state;
  const NewtonRun run = minimizeNewton(cost, x, state, s);
  EXPECT_TRUE(run.converged());
  EXPECT_EQ(run.iterations, 9);
  EXPECT_NEAR((x - cost.centre).norm(), 0.0, 1e-9);
  // With fewer iterations than that: the iteration limit, x as far as the budget took it.
  s.max_iterations = 3;
  x.setZero();
  const NewtonRun limited = minimizeNewton(cost, x, state, s);
  EXPECT_EQ(limited.outcome, NewtonOutcome::IterationLimit);
  EXPECT_EQ(limited.iterations, 3);
  EXPECT_NEAR(x.x(), 1.5, 1e-12);
  // No iteration left: the state is still evaluated at x (what the diagnostics read), x unchanged.
  s.max_iterations = 0;
  x = Eigen::Vector3d(1.0, 0.0, 0.0);
  const int before = cost.evaluations;
  EXPECT_EQ(minimizeNewton(cost, x, state, s).outcome, NewtonOutcome::IterationLimit);
  EXPECT_EQ(cost.evaluations, before + 1);
  EXPECT_DOUBLE_EQ(state.f, 9.0);
}

TEST(NewtonOptimizer, AZeroHessianHasNoDirection) {
  struct Flat {
    double operator()(const Eigen::Vector3d&, Eigen::Vector3d* g, Eigen::Matrix3d* H, int*) const {
      if (g) g->setZero();
      if (H) H->setZero();
      return 0.0;
    }
  } cost;
  Eigen::Vector3d x(0.1, 0.2, 0.0);
  NewtonState<int> state;
  const NewtonRun run = minimizeNewton(cost, x, state, settingsFor(3.0));
  EXPECT_EQ(run.outcome, NewtonOutcome::NoDirection);
  EXPECT_EQ(x, Eigen::Vector3d(0.1, 0.2, 0.0));
}

TEST(NewtonOptimizer, TheDirectionMirrorsAndFloorsTheHessiansEigenvalues) {
  // An indefinite Hessian diag(2, −4, 1e-9): the direction uses |λ| floored at 1e-6 · 4.
  const Eigen::Matrix3d H = Eigen::Vector3d(2.0, -4.0, 1e-9).asDiagonal();
  const Eigen::Vector3d g(1.0, 1.0, 1.0);
  Eigen::Vector3d step;
  ASSERT_TRUE(newtonDirection(H, g, &step, 1e-6));
  EXPECT_NEAR(step.x(), -0.5, 1e-12);
  EXPECT_NEAR(step.y(), -0.25, 1e-12);
  EXPECT_NEAR(step.z(), -1.0 / 4e-6, 1e-3);
  EXPECT_LT(g.dot(step), 0.0) << "a descent direction";
  EXPECT_FALSE(newtonDirection(Eigen::Matrix3d::Zero(), g, &step));
  EXPECT_FALSE(newtonDirection(Eigen::Matrix3d::Constant(std::nan("")), g, &step));
}

TEST(NewtonOptimizer, LimitToleranceAndStationaryRegionMeasureTheirOwnParts) {
  const StepLimit limit{1.0, 0.1};
  Eigen::Vector3d step(3.0, 4.0, 0.05);  // 5 m: scaled by 1/5, the rotation with it
  limit.apply(step);
  EXPECT_NEAR(step.head<2>().norm(), 1.0, 1e-12);
  EXPECT_NEAR(step.z(), 0.01, 1e-12);
  step = Eigen::Vector3d(0.3, 0.4, 0.5);  // the rotation binds: scaled by 0.2
  limit.apply(step);
  EXPECT_NEAR(step.z(), 0.1, 1e-12);
  EXPECT_NEAR(step.x(), 0.06, 1e-12);

  const StepTolerance tolerance{1e-6, std::cos(1e-4)};
  EXPECT_TRUE(tolerance.isSmall(Eigen::Vector3d(5e-4, 5e-4, 5e-5)));
  EXPECT_FALSE(tolerance.isSmall(Eigen::Vector3d(1e-3, 1e-3, 0.0))) << "translation above (1 mm)²";
  EXPECT_FALSE(tolerance.isSmall(Eigen::Vector3d(0.0, 0.0, 2e-4))) << "rotation above 0.1 mrad";

  const StationaryRegion region{0.15, 0.01};
  EXPECT_TRUE(region.contains(Eigen::Vector3d(0.1, 0.1, -0.01)));
  EXPECT_FALSE(region.contains(Eigen::Vector3d(0.12, 0.12, 0.0)));
  EXPECT_FALSE(region.contains(Eigen::Vector3d(0.0, 0.0, 0.011)));
}

TEST(NewtonOptimizer, TheLineSearchHalvesUntilArmijosConditionHolds) {
  // f = x² from x = 1 with a step of −4 (twice past the minimum): 1 → 9 fails, the half-step
  // −2 gives 1 (no decrease, fails), the quarter −1 reaches 0 and passes.
  struct Parabola {
    double operator()(const Eigen::Vector3d& x, Eigen::Vector3d* g, Eigen::Matrix3d* H, int*) const {
      if (g) *g = Eigen::Vector3d(2.0 * x.x(), 0.0, 0.0);
      if (H) *H = Eigen::Vector3d(2.0, 0.0, 0.0).asDiagonal();
      return x.x() * x.x();
    }
  } cost;
  NewtonSettings s = settingsFor(10.0);
  NewtonState<int> state, next;
  const Eigen::Vector3d x(1.0, 0.0, 0.0);
  state.f = cost(x, &state.g, &state.H, nullptr);
  const Eigen::Vector3d step(-4.0, 0.0, 0.0);
  bool with_derivatives = true;
  EXPECT_EQ(lineSearch(cost, x, state, step, state.g.dot(step), s, next, &with_derivatives), 0.25);
  EXPECT_FALSE(with_derivatives) << "only the full step is evaluated with derivatives";
  s.max_halvings = 2;  // the full step and one half: neither passes
  EXPECT_EQ(lineSearch(cost, x, state, step, state.g.dot(step), s, next, &with_derivatives), 0.0);
}
