// SPDX-License-Identifier: Apache-2.0
#pragma once
// Block-Jacobi conjugate gradients (BlockConjugateGradient) as a LinearSolver: an inexact solve,
// to a relative residual, for inexact Newton (the outer iteration tightens the rest).

#include <algorithm>

#include "numerics/BlockConjugateGradient.h"
#include "numerics/LinearSolver.h"

namespace tissuesim {

class ConjugateGradientSolver final : public LinearSolver {
 public:
  /// @param tolerance ||b - A x|| <= tolerance ||b||; at most 3#V products.
  explicit ConjugateGradientSolver(double tolerance) : m_tolerance(tolerance) {}

  const char* name() const override { return "conjugate gradients"; }
  bool isDirect() const override { return false; }
  void setThreadPool(ForkJoinPool* pool) override { m_cg.setThreadPool(pool); }

  LinearSolveReport solve(const BlockLinearOperator& a, const Eigen::VectorXd& b,
                          Eigen::VectorXd& x, std::span<const RankOneTerm> exactTerms,
                          bool isWarm) override {
    const ConjugateGradientReport cg =
        m_cg.solve(a, b, x, m_tolerance, static_cast<int>(3 * a.nodeCount()), exactTerms, isWarm);
    // A stall close to the tolerance is still a usable Newton direction.
    return {cg.converged || cg.relativeResidual < std::max(1e-6, m_tolerance), cg.iterations,
            cg.relativeResidual};
  }

 private:
  double m_tolerance;
  BlockConjugateGradient m_cg;
};

}  // namespace tissuesim
