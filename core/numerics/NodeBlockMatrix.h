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

  /// The same for edge e of the constructor's list (its nodes a = edges(0, e), b = edges(1, e)),
  /// from offsets found once at construction: no search in the assembly loop.
  void addEdgeStiffness(Eigen::Index e, const double* k) {
    const EdgeSlots& at = m_edgeSlots[static_cast<std::size_t>(e)];
    double* values = m_matrix.valuePtr();
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r < 3; ++r) {
        const double v = k[3 * c + r];
        values[at.aa + c * at.strideA + r] += v;
        values[at.ba + c * at.strideA + r] -= v;
        values[at.bb + c * at.strideB + r] += v;
        values[at.ab + c * at.strideB + r] -= v;
      }
    }
  }

  /// Adds `value` to the three diagonal entries of node i (a lumped mass, say).
  void addToDiagonal(int i, double value);

  /// For every DOF d with isFixed[d]: zeroes row and column d and puts 1 on the diagonal.
  /// @param isFixed 3#V flags. The entries it touches are listed once per set of flags (the
  /// first call, and whenever the flags change), so repeated calls visit only those entries.
  void applyFixedDofs(const std::vector<char>& isFixed);

  /// y = A x (both 3#V).
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const { y.noalias() = m_matrix * x; }

  const Eigen::SparseMatrix<double>& matrix() const { return m_matrix; }
  /// #E, the constructor's edge count.
  Eigen::Index edgeCount() const { return static_cast<Eigen::Index>(m_edgeSlots.size()); }

 private:
  Eigen::Index blockStart(int i, int j) const;

  /// Where edge (a, b)'s four blocks start in the value array; column c of a block in node j's
  /// columns is `stride` values after column c - 1.
  struct EdgeSlots {
    Eigen::Index aa, bb, ab, ba;  ///< starts of blocks (a, a), (b, b), (a, b) and (b, a)
    Eigen::Index strideA, strideB;  ///< 3 x neighbour count of a and of b
  };

  Eigen::SparseMatrix<double> m_matrix;
  std::vector<std::vector<int>> m_neighbours;  ///< per node, sorted, itself included
  std::vector<EdgeSlots> m_edgeSlots;          ///< per edge of the constructor's list
  std::vector<char> m_fixedFlags;              ///< the flags m_fixedEntries were listed for
  std::vector<Eigen::Index> m_fixedEntries;    ///< values zeroed by applyFixedDofs
  std::vector<Eigen::Index> m_fixedDiagonal;   ///< values set to 1 by applyFixedDofs
};

}  // namespace tissuesim
