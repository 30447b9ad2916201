// SPDX-License-Identifier: Apache-2.0
#pragma once
// The diagonal blocks that rank-one terms k u u^T add to a node-block matrix, per node they
// touch: D_j = sum over terms and their blocks at j of k u_j u_j^T (3x3, N/m). What block Jacobi
// needs of the instrument's contacts, in CG's preconditioner and the matrix-free operator's
// diagonal. A slot per node, set and cleared in O(terms): no pass over the nodes, and no
// allocation for up to the reserved number of terms.

#include <span>
#include <vector>

#include <Eigen/Core>

#include "numerics/RankOneTerm.h"

namespace tissuesim {

class RankOneTermDiagonals {
 public:
  /// Sizes for #V nodes and room for `reservedTerms` terms (three nodes each); clears.
  void resize(Eigen::Index nodeCount, std::size_t reservedTerms);
  /// Replaces the sums with the given terms' (a zero u block leaves its node out).
  void set(std::span<const RankOneTerm> terms);
  void clear();
  /// D_j, or null where no term touches node j.
  const Eigen::Matrix3d* at(Eigen::Index j) const {
    const int slot = m_slot[static_cast<std::size_t>(j)];
    return slot < 0 ? nullptr : &m_sums[static_cast<std::size_t>(slot)];
  }

 private:
  std::vector<int> m_slot;              ///< #V: index into m_sums, or -1
  std::vector<int> m_nodes;             ///< the nodes the terms touch
  std::vector<Eigen::Matrix3d> m_sums;  ///< D_j per such node
};

}  // namespace tissuesim
