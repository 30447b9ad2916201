// SPDX-License-Identifier: Apache-2.0
#pragma once
// Newton's method for the nonlinear systems of implicit Euler and of static equilibrium:
//
//   r(x) = w M (x - x_hat) - f(x) = 0                        (N; fixed DOFs excluded)
//   (K(x) + (w + rho) M) dx = -r(x),   x <- x + a dx         (a from a backtracking search on |r|)
//
// with K the stiffness (MechanicalSystem): with Cholesky, the exact Hessian first, for Newton's
// quadratic convergence, and the per-spring PSD projection whenever the exact matrix is not
// positive definite (a non-positive pivot) or gives no descent; with CG, always the projection,
// w >= 0 the inertia weight (1/s^2: (1 + alpha h) / h^2 for implicit Euler, 0 for statics) and
// rho >= 0 a Levenberg-Marquardt regularisation that keeps the matrix definite where K alone is
// singular (statics). When a factorisation fails or no step length reduces |r|, a
// Levenberg-Marquardt shift mu I is added (raised tenfold each time, relaxed after a good step);
// the solve stops, unconverged, when even a vanishing gradient step gives no descent (a kink in the
// force, say) and reports it. K is the system's force fields' (forces/ForceField.h), which each
// pass keeps at the iterate or at a line-search trial. Linear solves behind LinearSolver: an
// iterative one (conjugate gradients, ConjugateGradientSolver: on the system's thread pool when
// it has one) runs matrix-free on SystemOperator; a direct one (sparse Cholesky, CholeskySolver)
// on the matrix the fields assemble.

#include <array>
#include <memory>

#include "numerics/LinearSolver.h"
#include "numerics/NodeBlockMatrix.h"
#include "parallel/NodeRanges.h"
#include "system/MechanicalSystem.h"
#include "system/SystemOperator.h"

namespace tissuesim {

enum class LinearSolverKind { Cholesky, ConjugateGradient };

/// The solver of that kind; `tolerance`: an iterative one's relative residual.
std::unique_ptr<LinearSolver> makeLinearSolver(LinearSolverKind kind, double tolerance);

/// Norms of a residual r (N): max |r_i| (NaN when any entry is not finite) and ||r||^2, its
/// per-range partial sums (parallel/NodeRanges.h) added in range order.
struct ResidualNorms {
  double largest_N = 0.0;
  double squared_N2 = 0.0;
};

struct NewtonReport {
  int iterations = 0;
  int linearIterations = 0;  ///< CG iterations summed over the Newton iterations (0: Cholesky)
  double residual_N = 0.0;   ///< max |r_i| at the end
  double initialResidual_N = 0.0;  ///< max |r_i| at the start
  bool converged = false;
  ForceReport forces;
};

class NewtonSolver {
 public:
  explicit NewtonSolver(LinearSolverKind kind, double linearTolerance = 1e-6)
      : m_linearSolver(makeLinearSolver(kind, linearTolerance)) {}

  /// Up to `count` iterations beyond a solve's budget while max |r| stays above residual_N (a
  /// real-time step's budget is one iteration; a step that leaves a residual a trainee could
  /// feel takes more). Default: none.
  void setExtraIterations(int count, double residual_N) {
    m_extraIterations = count;
    m_extraIterationResidual_N = residual_N;
  }

  /// Solves from the initial guess in x (3 by #V), overwriting it; fixed DOFs are not moved.
  NewtonReport solve(MechanicalSystem& system, Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& xHat,
                     double inertiaWeight, double regularization, int maxIterations,
                     double tolerance_N);

 private:
  ResidualNorms residual(const MechanicalSystem& system, const Eigen::Matrix3Xd& x,
                         const Eigen::Matrix3Xd& xHat, double inertiaWeight, Eigen::Matrix3Xd& r,
                         ForceReport* report);
  /// r from the forces already in m_force (those at x), and its norms, in one node-wise pass
  /// (parallel/NodeRanges.h).
  ResidualNorms residualFromForce(const MechanicalSystem& system, const Eigen::Matrix3Xd& x,
                                  const Eigen::Matrix3Xd& xHat, double inertiaWeight,
                                  Eigen::Matrix3Xd& r);
  void prepare(MechanicalSystem& system);
  /// Forces at x into m_force, and the fields' stiffness there into their current or trial slot.
  ForceReport forcesAndStiffness(const MechanicalSystem& system, const Eigen::Matrix3Xd& x,
                                 StiffnessSlot slot, bool isProjected);

  std::unique_ptr<LinearSolver> m_linearSolver;
  int m_extraIterations = 0;
  double m_extraIterationResidual_N = 0.0;
  const MechanicalSystem* m_preparedFor = nullptr;
  // The operator A: assembled from the fields for a direct solver, else matrix-free.
  std::unique_ptr<NodeBlockMatrix> m_matrix;
  std::unique_ptr<SystemOperator> m_operator;
  Eigen::Matrix3Xd m_force, m_r, m_trialR, m_trialX;
  Eigen::VectorXd m_rhs, m_step;
  /// The last time step's first Newton step (iterative solves): the next step's first solve
  /// starts from it, zero (a cold start) until there is one.
  Eigen::VectorXd m_firstStep;
  // residualFromForce's partials, one per node range.
  std::array<double, kNodeRanges> m_rangeLargest{};
  std::array<double, kNodeRanges> m_rangeSquares{};
};

}  // namespace tissuesim
