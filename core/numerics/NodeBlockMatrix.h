// SPDX-License-Identifier: Apache-2.0
#pragma once
// A sparse symmetric matrix of 3x3 node blocks (3#V by 3#V), with the pattern of a graph's
// edges plus the diagonal, fixed at construction so that assembling into it never allocates:
// values are overwritten in place and a Cholesky factorisation can keep its symbolic analysis.
//
// In Eigen's column-major storage the column of DOF 3j + c holds, for each neighbour i of node j
// (sorted, j included), the three rows 3i .. 3i+2 contiguously; so block (i, j) starts at
// outer[3j + c] + 3 * (position of i among j's neighbours).

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "numerics/AxialBlocks.h"
#include "numerics/BlockLinearOperator.h"
#include "numerics/NodeBlockProduct.h"
#include "parallel/ForkJoinPool.h"

namespace tissuesim {

class NodeBlockMatrix final : public BlockLinearOperator {
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

  /// Overwrites every stored value with the edges' stiffness (9 by #B, a column-major 3x3 K_e
  /// per edge of the constructor's list, the first #B <= #E edges; the others' blocks zero): the
  /// matrix setZero() and addEdgeStiffness() on those edges give (up to the order of the
  /// diagonal sums), written column by column, each value once, with no clearing pass. On `pool`
  /// (when given, with more than one thread) the nodes' columns are written in kParts ranges at
  /// once; the values are the same.
  void assignEdgeStiffness(const Eigen::Matrix<double, 9, Eigen::Dynamic>& k,
                           ForkJoinPool* pool = nullptr);
  /// The same from blocks in the axial form c n n^T + l I (numerics/AxialBlocks.h), each
  /// expanded as it is written.
  void assignAxialEdgeStiffness(const AxialBlocks& k, ForkJoinPool* pool = nullptr);
  /// The same, added to what the matrix holds (another force's stiffness, say).
  void addAxialEdgeStiffness(const AxialBlocks& k, ForkJoinPool* pool = nullptr);

  /// Adds `value` to the three diagonal entries of node i (a lumped mass, say).
  void addToDiagonal(int i, double value);

  /// For every DOF d with isFixed[d]: zeroes row and column d and puts 1 on the diagonal.
  /// @param isFixed 3#V flags. The entries it touches are listed once per set of flags (the
  /// first call, and whenever the flags change), so repeated calls visit only those entries.
  void applyFixedDofs(const std::vector<char>& isFixed);

  /// Rows 3j .. 3j+2 of y = A x for the nodes j in [begin, end) only: by symmetry row 3j+c is
  /// column 3j+c, so each is one dot product of a stored column with j's neighbours' x
  /// (numerics/NodeBlockProduct.h, SIMD). Disjoint node ranges can run on different threads.
  void multiplyNodes(Eigen::Index begin, Eigen::Index end, const double* x, double* y) const {
    multiplyNodeRows(rows(), begin, end, x, y);
  }
  /// What the product kernels read (pointers into this matrix).
  NodeBlockRows rows() const {
    return {m_matrix.valuePtr(), m_matrix.outerIndexPtr(), m_neighbourStart.data(),
            m_neighbourIndex.data()};
  }

  /// BlockLinearOperator: node ranges of about equal stored values, each part's rows by
  /// multiplyNodes().
  const PartBounds& partBounds() const override { return m_partBounds; }
  void multiplyPart(int part, const double* x, double* y) const override {
    multiplyNodes(m_partBounds[static_cast<std::size_t>(part)],
                  m_partBounds[static_cast<std::size_t>(part) + 1], x, y);
  }

  const NodeBlockMatrix* assembled() const override { return this; }

  /// Block (j, j), 3x3.
  Eigen::Matrix3d diagonalBlock(Eigen::Index j) const override {
    const double* start = m_matrix.valuePtr() + m_diagonalStart[static_cast<std::size_t>(j)];
    const Eigen::Index stride = blockStride(static_cast<int>(j));
    Eigen::Matrix3d block;
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r < 3; ++r) block(r, c) = start[c * stride + r];
    }
    return block;
  }

  /// #V.
  Eigen::Index nodeCount() const override {
    return static_cast<Eigen::Index>(m_neighbourStart.size()) - 1;
  }
  /// Stored values in the columns of nodes [0, j): a cost measure for cutting node ranges.
  Eigen::Index valuesBefore(Eigen::Index j) const { return m_matrix.outerIndexPtr()[3 * j]; }

  const Eigen::SparseMatrix<double>& matrix() const { return m_matrix; }
  /// #E, the constructor's edge count.
  Eigen::Index edgeCount() const { return static_cast<Eigen::Index>(m_edgeSlots.size()); }

 private:
  /// assignEdgeStiffness() from blockOf(e) (a column-major 3x3 block, Eigen::Matrix3d); added to
  /// the values when IsAdded.
  template <bool IsAdded, typename BlockOf>
  void assignEdges(Eigen::Index blockCount, const BlockOf& blockOf, ForkJoinPool* pool);
  /// The same for the columns of nodes [begin, end).
  template <bool IsAdded, typename BlockOf>
  void assignNodeColumns(const BlockOf& blockOf, Eigen::Index blockCount, Eigen::Index begin,
                         Eigen::Index end);
  /// Where node i stands in m_neighbourIndex among j's neighbours; throws if no edge joins them.
  std::size_t neighbourSlot(int i, int j) const;
  /// Where the block at `slot` (an entry of m_neighbourIndex among j's) starts in the values.
  Eigen::Index slotStart(std::size_t slot, int j) const;
  Eigen::Index blockStart(int i, int j) const;
  /// Values between column c and c + 1 of a block in node j's columns: 3 x j's neighbour count.
  Eigen::Index blockStride(int j) const {
    return 3 * static_cast<Eigen::Index>(m_neighbourStart[static_cast<std::size_t>(j) + 1] -
                                         m_neighbourStart[static_cast<std::size_t>(j)]);
  }

  /// Where edge (a, b)'s four blocks start in the value array; column c of a block in node j's
  /// columns is `stride` values after column c - 1.
  struct EdgeSlots {
    Eigen::Index aa, bb, ab, ba;    ///< starts of blocks (a, a), (b, b), (a, b) and (b, a)
    Eigen::Index strideA, strideB;  ///< 3 x neighbour count of a and of b
  };

  Eigen::SparseMatrix<double> m_matrix;
  // Per node j, its neighbours (sorted, j included) are m_neighbourIndex[m_neighbourStart[j] ..
  // m_neighbourStart[j + 1]).
  std::vector<int> m_neighbourStart;  ///< #V + 1
  std::vector<int> m_neighbourIndex;
  std::vector<Eigen::Index> m_diagonalStart;  ///< per node j, where block (j, j) starts
  std::vector<EdgeSlots> m_edgeSlots;         ///< per edge of the constructor's list
  /// Per entry of m_neighbourIndex, the edge joining the two nodes (-1 on the diagonal).
  std::vector<int> m_neighbourEdge;
  /// Node ranges of equal shares of the stored values: the product's parts and the assignment's.
  PartBounds m_partBounds{};
  bool m_hasRepeatedEdges = false;  ///< an edge listed twice: assignEdgeStiffness() must add
  std::vector<char> m_fixedFlags;   ///< the flags m_fixedEntries were listed for
  std::vector<Eigen::Index> m_fixedEntries;   ///< values zeroed by applyFixedDofs
  std::vector<Eigen::Index> m_fixedDiagonal;  ///< values set to 1 by applyFixedDofs
};

}  // namespace tissuesim
