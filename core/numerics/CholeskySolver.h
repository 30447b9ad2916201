// SPDX-License-Identifier: Apache-2.0
#pragma once
// Sparse Cholesky (Eigen's SimplicialLDLT) as a LinearSolver: a direct solve of an assembled
// NodeBlockMatrix, its symbolic analysis done once per matrix (the pattern is fixed). A matrix
// that is not positive definite (a non-positive pivot) is reported as not solved.

#include <Eigen/SparseCholesky>

#include "numerics/LinearSolver.h"

namespace tissuesim {

class CholeskySolver final : public LinearSolver {
 public:
  const char* name() const override { return "Cholesky"; }
  bool isDirect() const override { return true; }

  /// Throws std::logic_error when `a` is not assembled.
  LinearSolveReport solve(const BlockLinearOperator& a, const Eigen::VectorXd& b,
                          Eigen::VectorXd& x, std::span<const RankOneTerm> exactTerms,
                          bool isWarm) override;

 private:
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> m_cholesky;
  const void* m_analysedFor = nullptr;  ///< the matrix whose pattern was analysed
};

}  // namespace tissuesim
