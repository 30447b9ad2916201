// SPDX-License-Identifier: Apache-2.0
#include "numerics/CholeskySolver.h"

#include <stdexcept>

#include "numerics/NodeBlockMatrix.h"

namespace tissuesim {

LinearSolveReport CholeskySolver::solve(const BlockLinearOperator& a, const Eigen::VectorXd& b,
                                        Eigen::VectorXd& x, std::span<const RankOneTerm>, bool) {
  const NodeBlockMatrix* matrix = a.assembled();
  if (matrix == nullptr) throw std::logic_error("CholeskySolver: the operator is not assembled");
  if (m_analysedFor != matrix) {
    m_cholesky.analyzePattern(matrix->matrix());
    m_analysedFor = matrix;
  }
  m_cholesky.factorize(matrix->matrix());
  LinearSolveReport report;
  report.isSolved =
      m_cholesky.info() == Eigen::Success && (m_cholesky.vectorD().array() > 0.0).all();
  if (report.isSolved) x = m_cholesky.solve(b);
  return report;
}

}  // namespace tissuesim
