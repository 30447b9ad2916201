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
// force, say) and reports it. Linear solves: sparse Cholesky (Eigen SimplicialLDLT, symbolic
// analysis once per pattern) or conjugate gradients (3x3 block-Jacobi preconditioner,
// BlockConjugateGradient: on the springs' thread pool when they have one). CG runs matrix-free
// (SpringSystemOperator, on the force pass's linearisation: springs and volume term); Cholesky
// needs the assembled matrix.

#include <array>
#include <memory>

#include <Eigen/SparseCholesky>

#include "numerics/BlockConjugateGradient.h"
#include "parallel/NodeRanges.h"

#include "integrators/SpringSystemOperator.h"

#include "integrators/TimeIntegrator.h"

namespace tissuesim {

enum class LinearSolverKind { Cholesky, ConjugateGradient };

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
      : m_kind(kind), m_linearTolerance(linearTolerance) {}

  /// Up to `count` iterations beyond a solve's budget while max |r| stays above residual_N (a
  /// real-time step's budget is one iteration; a step that leaves a residual a trainee could
  /// feel takes more). Default: none.
  void setExtraIterations(int count, double residual_N) {
    m_extraIterations = count;
    m_extraIterationResidual_N = residual_N;
  }

  /// Solves from the initial guess in x (3 by #V), overwriting it; fixed DOFs are not moved.
  NewtonReport solve(const MechanicalSystem& system, Eigen::Matrix3Xd& x,
                     const Eigen::Matrix3Xd& xHat, double inertiaWeight, double regularization,
                     int maxIterations, double tolerance_N);

 private:
  ResidualNorms residual(const MechanicalSystem& system, const Eigen::Matrix3Xd& x,
                         const Eigen::Matrix3Xd& xHat, double inertiaWeight, Eigen::Matrix3Xd& r,
                         ForceReport* report);
  /// r from the forces already in m_force (those at x), and its norms, in one node-wise pass
  /// (parallel/NodeRanges.h).
  ResidualNorms residualFromForce(const MechanicalSystem& system, const Eigen::Matrix3Xd& x,
                                  const Eigen::Matrix3Xd& xHat, double inertiaWeight,
                                  Eigen::Matrix3Xd& r);
  void prepare(const MechanicalSystem& system);
  /// Forces at x into m_force and the stiffness there into the matrix or the spring blocks
  /// (the trial's when `isTrial`).
  ForceReport forcesAndStiffness(const MechanicalSystem& system, const Eigen::Matrix3Xd& x,
                                 bool isTrial, bool isProjected);

  LinearSolverKind m_kind;
  double m_linearTolerance;  ///< CG's relative residual (inexact Newton)
  int m_extraIterations = 0;
  double m_extraIterationResidual_N = 0.0;
  const MechanicalSystem* m_preparedFor = nullptr;
  bool m_isMatrixFree = false;  ///< CG on SpringSystemOperator; else on the assembled matrix
  // Assembled (Cholesky):
  std::unique_ptr<NodeBlockMatrix> m_matrix;
  std::unique_ptr<NodeBlockMatrix> m_trialMatrix;  ///< the line search's trials' stiffness
  // Matrix-free: the linearisation at the iterate and at the line search's trials.
  std::unique_ptr<SpringSystemOperator> m_operator;
  SystemLinearization m_linearization, m_trialLinearization;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> m_cholesky;
  BlockConjugateGradient m_cg;
  bool m_isPatternAnalysed = false;
  Eigen::Matrix3Xd m_force, m_r, m_trialR, m_trialX;
  Eigen::VectorXd m_rhs, m_step;
  /// The last time step's first Newton step (CG): the next step's first CG starts from it, zero
  /// (a cold start) until there is one.
  Eigen::VectorXd m_firstStep;
  std::vector<RankOneTerm> m_contactTerms;  ///< the contacts' stiffness, for CG's preconditioner
  // residualFromForce's partials, one per node range.
  std::array<double, kNodeRanges> m_rangeLargest{};
  std::array<double, kNodeRanges> m_rangeSquares{};
};

}  // namespace tissuesim
