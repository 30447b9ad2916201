// SPDX-License-Identifier: Apache-2.0
#pragma once
// The springs' part of Newton's matrix-free product, y += K x, with
//
//   K = sum_e S_e^T [K_e, -K_e; -K_e, K_e] S_e,   K_e = c_e n_e n_e^T + l_e I             (N/m)
//
// spring e's block on its ends (a, b), read from the force pass's AxialBlocks (5 by #S:
// numerics/AxialBlocks.h). Why matrix-free: an assembled NodeBlockMatrix stores two 72-byte
// blocks a spring plus the diagonal, filled by a pass of its own after the spring pass; this
// reads the pass's 40 bytes a spring, and K_e (x_b - x_a) = c n (n . d) + l d costs about what a
// block row costs (docs/performance.md has the measurements).
//
// Parallel parts: node ranges given by the operator. Part p evaluates every spring with an end
// among its nodes and adds to those ends only; a spring joining two parts is evaluated by both,
// each adding to its own end. No two parts write the same row, and each row's sum runs in a
// fixed order, so products are bit-identical for any thread count.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "numerics/AxialBlocks.h"
#include "numerics/BlockLinearOperator.h"
#include "springs/SpringMesh.h"

namespace tissuesim {

class SpringStiffnessProduct {
 public:
  static constexpr int kParts = BlockLinearOperator::kParts;
  using PartBounds = BlockLinearOperator::PartBounds;

  /// `mesh` must outlive this object. Throws std::invalid_argument when 3#V overflows an int.
  SpringStiffnessProduct(const SpringMesh& mesh, const PartBounds& bounds);

  const PartBounds& bounds() const { return m_bounds; }

  /// Rows of part p's nodes: y += K x (K from `blocks`, 5 by #S).
  void addPart(int part, const AxialBlocks& blocks, const double* x, double* y) const;
  /// block += sum over node j's springs of K_e.
  void addDiagonalBlock(Eigen::Index j, const AxialBlocks& blocks, Eigen::Matrix3d& block) const;

  /// nodeWork[j] += node j's spring count.
  static void addWork(const SpringMesh& mesh, std::vector<Eigen::Index>& nodeWork);

 private:
  /// A spring as the product reads it: where its ends' rows start (3a, 3b) and its index.
  struct Entry {
    int rowA;
    int rowB;
    int spring;
  };
  /// The springs [begin, end) of m_entries into y, each on its a row (when AddA) and its b row
  /// (when AddB).
  template <bool AddA, bool AddB>
  void addRange(std::size_t begin, std::size_t end, const double* k, const double* x,
                double* y) const;

  PartBounds m_bounds;
  // Per part, three lists in spring order: the springs with both ends among its nodes, those with
  // only a, those with only b; m_listStart[p] = {both, a only, b only, end} into m_entries. Three
  // lists, not one with flags: the loops then have no branch but the run's (measured 20 % faster).
  std::vector<Entry> m_entries;
  std::array<std::array<std::size_t, 4>, kParts> m_listStart{};
  // Per node j, its springs are m_incident[m_incidentStart[j] .. m_incidentStart[j + 1]).
  std::vector<int> m_incidentStart;
  std::vector<int> m_incident;
};

}  // namespace tissuesim
