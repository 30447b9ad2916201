// SPDX-License-Identifier: Apache-2.0
#include "numerics/NodeBlockMatrix.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace tissuesim {

NodeBlockMatrix::NodeBlockMatrix(Eigen::Index nodeCount, const Eigen::Matrix2Xi& edges) {
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(nodeCount));
  for (Eigen::Index v = 0; v < nodeCount; ++v)
    neighbours[static_cast<std::size_t>(v)].push_back(static_cast<int>(v));
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    neighbours[static_cast<std::size_t>(edges(0, e))].push_back(edges(1, e));
    neighbours[static_cast<std::size_t>(edges(1, e))].push_back(edges(0, e));
  }
  Eigen::Index nonZeros = 0;
  m_neighbourStart.reserve(static_cast<std::size_t>(nodeCount) + 1);
  m_neighbourStart.push_back(0);
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    nonZeros += 9 * static_cast<Eigen::Index>(list.size());
    m_neighbourIndex.insert(m_neighbourIndex.end(), list.begin(), list.end());
    m_neighbourStart.push_back(static_cast<int>(m_neighbourIndex.size()));
  }
  const Eigen::Index size = 3 * nodeCount;
  m_matrix.resize(size, size);
  m_matrix.reserve(nonZeros);
  // Insert column by column in order: Eigen builds the compressed pattern directly.
  for (Eigen::Index j = 0; j < nodeCount; ++j) {
    for (int c = 0; c < 3; ++c) {
      const Eigen::Index column = 3 * j + c;
      m_matrix.startVec(column);
      for (const int i : neighbours[static_cast<std::size_t>(j)]) {
        for (int r = 0; r < 3; ++r) m_matrix.insertBack(3 * i + r, column) = 0.0;
      }
    }
  }
  m_matrix.finalize();
  m_diagonalStart.reserve(static_cast<std::size_t>(nodeCount));
  for (Eigen::Index j = 0; j < nodeCount; ++j)
    m_diagonalStart.push_back(blockStart(static_cast<int>(j), static_cast<int>(j)));
  // Per edge, one search for each end's slot: it gives both the blocks' offsets and the
  // assignment's edge map.
  m_edgeSlots.reserve(static_cast<std::size_t>(edges.cols()));
  m_neighbourEdge.assign(m_neighbourIndex.size(), -1);
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    const int a = edges(0, e);
    const int b = edges(1, e);
    const std::size_t aAmongB = neighbourSlot(a, b);
    const std::size_t bAmongA = neighbourSlot(b, a);
    m_edgeSlots.push_back({m_diagonalStart[static_cast<std::size_t>(a)],
                           m_diagonalStart[static_cast<std::size_t>(b)], slotStart(aAmongB, b),
                           slotStart(bAmongA, a), blockStride(a), blockStride(b)});
    for (const std::size_t at : {aAmongB, bAmongA}) {
      if (m_neighbourEdge[at] != -1) m_hasRepeatedEdges = true;
      m_neighbourEdge[at] = static_cast<int>(e);
    }
  }
  m_partBounds =
      balancedPartBounds(this->nodeCount(), [this](Eigen::Index j) { return valuesBefore(j); });
}

void NodeBlockMatrix::assignEdgeStiffness(const Eigen::Matrix<double, 9, Eigen::Dynamic>& k,
                                          ForkJoinPool* pool) {
  assignEdges<false>(
      k.cols(), [&](Eigen::Index e) { return Eigen::Map<const Eigen::Matrix3d>(k.col(e).data()); },
      pool);
}

void NodeBlockMatrix::assignAxialEdgeStiffness(const AxialBlocks& k, ForkJoinPool* pool) {
  assignEdges<false>(
      k.cols(), [&](Eigen::Index e) { return axialBlock(k.col(e).data()); }, pool);
}

void NodeBlockMatrix::addAxialEdgeStiffness(const AxialBlocks& k, ForkJoinPool* pool) {
  assignEdges<true>(
      k.cols(), [&](Eigen::Index e) { return axialBlock(k.col(e).data()); }, pool);
}

template <bool IsAdded, typename BlockOf>
void NodeBlockMatrix::assignEdges(Eigen::Index blockCount, const BlockOf& blockOf,
                                  ForkJoinPool* pool) {
  if (blockCount > edgeCount()) {
    throw std::invalid_argument(
        "NodeBlockMatrix::assignEdgeStiffness: " + std::to_string(blockCount) + " blocks for " +
        std::to_string(edgeCount()) + " edges");
  }
  if (m_hasRepeatedEdges) {  // two edges share a block: they must be summed
    if constexpr (!IsAdded) setZero();
    for (Eigen::Index e = 0; e < blockCount; ++e) {
      const Eigen::Matrix3d block = blockOf(e);
      addEdgeStiffness(e, block.data());
    }
    return;
  }
  // Each node's columns are written from its own edges' blocks only: node ranges are
  // independent, and the values written do not depend on how the nodes are cut.
  const auto part = [&](int p) {
    assignNodeColumns<IsAdded>(blockOf, blockCount, m_partBounds[static_cast<std::size_t>(p)],
                               m_partBounds[static_cast<std::size_t>(p) + 1]);
  };
  runParts(pool, kParts, part);
}

template <bool IsAdded, typename BlockOf>
void NodeBlockMatrix::assignNodeColumns(const BlockOf& blockOf, Eigen::Index blockCount,
                                        Eigen::Index begin, Eigen::Index end) {
  double* const values = m_matrix.valuePtr();
  const int* const outer = m_matrix.outerIndexPtr();
  for (Eigen::Index j = begin; j < end; ++j) {
    const int first = m_neighbourStart[static_cast<std::size_t>(j)];
    const int count = m_neighbourStart[static_cast<std::size_t>(j) + 1] - first;
    const Eigen::Index stride = 3 * static_cast<Eigen::Index>(count);
    double* const column = values + outer[3 * j];
    // Block (i, j) of edge e is -K_e as addEdgeStiffness() writes it; (j, j) sums them.
    double diagonal[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    double* diagonalBlock = nullptr;
    for (int p = 0; p < count; ++p) {
      double* const block = column + 3 * p;
      const int e = m_neighbourEdge[static_cast<std::size_t>(first + p)];
      if (e < 0) {
        diagonalBlock = block;
        continue;
      }
      if (e >= blockCount) {  // an edge past the blocks given: a zero block
        if constexpr (!IsAdded) {
          for (int c = 0; c < 3; ++c) std::fill_n(block + c * stride, 3, 0.0);
        }
        continue;
      }
      const Eigen::Matrix3d ke = blockOf(e);
      for (int c = 0; c < 3; ++c) {
        for (int r = 0; r < 3; ++r) {
          if constexpr (IsAdded) {
            block[c * stride + r] -= ke(r, c);
          } else {
            block[c * stride + r] = -ke(r, c);
          }
          diagonal[3 * c + r] += ke(r, c);
        }
      }
    }
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r < 3; ++r) {
        if constexpr (IsAdded) {
          diagonalBlock[c * stride + r] += diagonal[3 * c + r];
        } else {
          diagonalBlock[c * stride + r] = diagonal[3 * c + r];
        }
      }
    }
  }
}

std::size_t NodeBlockMatrix::neighbourSlot(int i, int j) const {
  const auto first = m_neighbourIndex.begin() + m_neighbourStart[static_cast<std::size_t>(j)];
  const auto last = m_neighbourIndex.begin() + m_neighbourStart[static_cast<std::size_t>(j) + 1];
  const auto found = std::lower_bound(first, last, i);
  if (found == last || *found != i) {
    throw std::logic_error("NodeBlockMatrix: nodes " + std::to_string(i) + " and " +
                           std::to_string(j) + " share no edge");
  }
  return static_cast<std::size_t>(found - m_neighbourIndex.begin());
}

Eigen::Index NodeBlockMatrix::slotStart(std::size_t slot, int j) const {
  const auto position =
      static_cast<Eigen::Index>(slot) - m_neighbourStart[static_cast<std::size_t>(j)];
  return m_matrix.outerIndexPtr()[3 * j] + 3 * position;
}

Eigen::Index NodeBlockMatrix::blockStart(int i, int j) const {
  return slotStart(neighbourSlot(i, j), j);
}

void NodeBlockMatrix::addBlock(int i, int j, const Eigen::Matrix3d& block) {
  const Eigen::Index start = blockStart(i, j);
  const Eigen::Index stride = blockStride(j);
  double* values = m_matrix.valuePtr();
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) values[start + c * stride + r] += block(r, c);
  }
}

void NodeBlockMatrix::addEdgeStiffness(int a, int b, const Eigen::Matrix3d& k) {
  addBlock(a, a, k);
  addBlock(b, b, k);
  addBlock(a, b, -k);
  addBlock(b, a, -k);
}

void NodeBlockMatrix::addToDiagonal(int i, double value) {
  const Eigen::Index start = m_diagonalStart[static_cast<std::size_t>(i)];
  const Eigen::Index stride = blockStride(i);
  double* values = m_matrix.valuePtr();
  for (int c = 0; c < 3; ++c) values[start + c * stride + c] += value;
}

void NodeBlockMatrix::applyFixedDofs(const std::vector<char>& isFixed) {
  if (isFixed != m_fixedFlags) {
    // List the entries once for these flags (allocates only when the constraints change).
    m_fixedFlags = isFixed;
    m_fixedEntries.clear();
    m_fixedDiagonal.clear();
    const int* rows = m_matrix.innerIndexPtr();
    const int* outer = m_matrix.outerIndexPtr();
    for (Eigen::Index column = 0; column < m_matrix.outerSize(); ++column) {
      const bool isColumnFixed = isFixed[static_cast<std::size_t>(column)] != 0;
      for (int k = outer[column]; k < outer[column + 1]; ++k) {
        if (isColumnFixed || isFixed[static_cast<std::size_t>(rows[k])] != 0) {
          (rows[k] == column ? m_fixedDiagonal : m_fixedEntries).push_back(k);
        }
      }
    }
  }
  double* values = m_matrix.valuePtr();
  for (const Eigen::Index k : m_fixedEntries) values[k] = 0.0;
  for (const Eigen::Index k : m_fixedDiagonal) values[k] = 1.0;
}

}  // namespace tissuesim
