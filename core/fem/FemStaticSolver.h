// SPDX-License-Identifier: Apache-2.0
#pragma once
// Static equilibrium of the FEM model with prescribed displacements: Newton's method on
//
//   dE/dx = 0 on the free DOFs,   x fixed on the others (their values as the caller sets them)
//
// with the exact Hessian and a sparse direct solve (SuiteSparse's supernodal CHOLMOD through
// Eigen; the pattern is analysed once per set of fixed DOFs). Why CHOLMOD: on a block's 3D
// Hessians it factorises several times faster than Eigen's simplicial LDLT, which decides
// whether a refined reference runs in minutes or in an hour (docs/performance.md). Where the
// Hessian is not positive definite on the free DOFs (a non-positive pivot) a Levenberg-Marquardt
// shift mu I is added, raised tenfold until it is, relaxed after a good step. Each step is
// backtracked on the energy (Armijo), so an element that would invert or pass the chain's locking
// (infinite energy) is never stepped into.

#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "fem/FemModel.h"

namespace tissuesim {

struct FemSolveReport {
  bool converged = false;
  int iterations = 0;
  double residual_N = 0.0;  ///< max |dE/dx| on the free DOFs at the end
  FemState state;
};

class FemStaticSolver {
 public:
  /// converged when max |dE/dx| on the free DOFs <= tolerance_N.
  explicit FemStaticSolver(double tolerance_N = 1e-9, int maxIterations = 50);
  ~FemStaticSolver();

  void setTolerance(double tolerance_N) { m_tolerance_N = tolerance_N; }
  void setMaxIterations(int iterations) { m_maxIterations = iterations; }

  /// From the guess in x (3 by #V, admissible), overwritten; isFixed: 3#V flags.
  FemSolveReport solve(const FemModel& model, Eigen::Matrix3Xd& x,
                       const std::vector<char>& isFixed);

  /// The last solve's dE/dx (3 by #V) at its end: on a fixed DOF, the force the support exerts
  /// on the body there (a grip's pull; QuadraticTetWeight_test checks the sign).
  const Eigen::Matrix3Xd& gradient() const { return m_gradient; }

  /// The Hessian at x assembled and factorised (shifted by mu I where it is not positive definite
  /// on the free DOFs), and dE/dx there into gradient(): one Newton iteration's linear algebra,
  /// for a caller that steps on its own (fem/HapticRateFem.h). @returns false where x is not
  /// admissible or no shift within reach makes the matrix definite.
  bool factorize(const FemModel& model, const Eigen::Matrix3Xd& x, const std::vector<char>& isFixed,
                 FemState& state);
  /// Whether a factorisation stands to solve with: the last solve()'s or factorize()'s.
  bool isFactorized() const { return m_isFactorized; }
  /// rhs (3#V by any) overwritten by the last factorisation's solve; fixed DOFs' rows zero. Many
  /// columns (a contact's compliance) are solved in two halves on two threads (a ForkJoinPool the
  /// solver keeps), each half with a workspace of its own. @throws std::runtime_error where CHOLMOD
  /// runs out of memory.
  void solveFactorized(Eigen::MatrixXd& rhs) const;

 private:
  double m_tolerance_N;
  int m_maxIterations;
  Eigen::Matrix3Xd m_gradient, m_trialGradient, m_trial;
  Eigen::SparseMatrix<double> m_hessian;
  FemHessianAssembly m_assembly;  ///< m_hessian's pattern, kept from Hessian to Hessian
  class SupernodalCholesky;       // CHOLMOD's, kept out of this header
  struct Factorization;
  std::unique_ptr<Factorization> m_factorization;
  std::vector<char> m_analysedFixed;  ///< the fixed set the pattern was analysed for
  bool m_isFactorized = false;
  /// Factorises m_hessian plus shift on the free DOFs, raising shift tenfold until definite.
  bool factorizeShifted(const std::vector<char>& isFixed, double& shift);
};

}  // namespace tissuesim
