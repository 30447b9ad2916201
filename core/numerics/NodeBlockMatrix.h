#pragma once
// A sparse symmetric matrix of 3x3 node blocks (3#V by 3#V), with the pattern of a graph's
// edges plus the diagonal, fixed at construction so that assembling into it never allocates:
// values are overwritten in place and a Cholesky factorisation can keep its symbolic analysis.
//
// In Eigen's column-major storage the column of DOF 3j + c holds, for each neighbour i of node j
// (sorted, j included), the three rows 3i .. 3i+2 contiguously; so block (i, j) starts at
// outer[3j + c] + 3 * (position of i among j's neighbours).

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace tissuesim {

class NodeBlockMatrix {
 public:
  /// @param nodeCount #V; @param edges 2 by #E node pairs (each pair once, either order).
  NodeBlockMatrix(Eigen::Index nodeCount, const Eigen::Matrix2Xi& edges);

  void setZero() { m_matrix.coeffs().setZero(); }

  /// Adds `block` to (i, j). Both nodes must be equal or joined by an edge.
  void addBlock(int i, int j, const Eigen::Matrix3d& block);

  /// Adds K to (a, a) and (b, b) and -K to (a, b) and (b, a): a spring's Hessian.
  void addEdgeStiffness(int a, int b, const Eigen::Matrix3d& k);

  /// Adds `value` to the three diagonal entries of node i (a lumped mass, say).
  void addToDiagonal(int i, double value);

  /// For every DOF d with isFixed[d]: zeroes row and column d and puts 1 on the diagonal.
  /// @param isFixed 3#V flags.
  void applyFixedDofs(const std::vector<char>& isFixed);

  /// y = A x (both 3#V).
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const { y.noalias() = m_matrix * x; }

  const Eigen::SparseMatrix<double>& matrix() const { return m_matrix; }

 private:
  Eigen::Index blockStart(int i, int j) const;

  Eigen::SparseMatrix<double> m_matrix;
  std::vector<std::vector<int>> m_neighbours;  ///< per node, sorted, itself included
};

}  // namespace tissuesim
