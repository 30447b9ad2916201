// SPDX-License-Identifier: Apache-2.0
#pragma once
// A linear solver for Newton's systems A x = b on a BlockLinearOperator (A: 3#V by 3#V,
// symmetric; b, x: 3#V): iterative ones read A's products and diagonal blocks, direct ones
// factorise it assembled. Newton picks one and knows nothing else of it.

#include <span>

#include <Eigen/Core>

#include "numerics/BlockLinearOperator.h"
#include "numerics/RankOneTerm.h"
#include "parallel/ForkJoinPool.h"

namespace tissuesim {

struct LinearSolveReport {
  bool isSolved = false;          ///< x solves the system (to the solver's tolerance)
  int iterations = 0;             ///< iterative: products of A taken (0 for a direct solve)
  double relativeResidual = 0.0;  ///< iterative: ||b - A x|| / ||b|| at the end
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;

  virtual const char* name() const = 0;
  /// Direct: needs A assembled (BlockLinearOperator::assembled()) and reports an indefinite A as
  /// not solved, so Newton may offer it the exact Hessian first.
  virtual bool isDirect() const = 0;
  /// Runs on `pool` where the solver can use one (null: the caller's thread).
  virtual void setThreadPool(ForkJoinPool* pool) { (void)pool; }

  /// Solves A x = b into x. With `isWarm` an iterative solver starts from the x given (else 0).
  /// `exactTerms`: rank-one terms of A (zero on the fixed DOFs) worth treating exactly in a
  /// preconditioner; a direct solver has them in the matrix already.
  virtual LinearSolveReport solve(const BlockLinearOperator& a, const Eigen::VectorXd& b,
                                  Eigen::VectorXd& x, std::span<const RankOneTerm> exactTerms,
                                  bool isWarm) = 0;

 protected:
  LinearSolver() = default;
  LinearSolver(const LinearSolver&) = default;
  LinearSolver& operator=(const LinearSolver&) = default;
};

}  // namespace tissuesim
