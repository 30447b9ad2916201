#pragma once
// The volume term's part of Newton's matrix-free product, y += K x, with
//
//   K = sum_t c_t g_t g_t^T    (N/m; g_t = dV_t/dx on tet t's four nodes, c_t = kappa / V0)
//
// read from the force pass's VolumeBlocks (13 by #T): c g (g . x), no 12x12 block.
//
// Parallel parts: node ranges given by the operator. Part p takes g_t . x once for every tet
// with a node among its own, and adds to those nodes only: no two parts write one row, and each
// row's sum runs in a fixed order, so products are bit-identical for any thread count.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "numerics/BlockLinearOperator.h"

namespace tissuesim {

/// The volume term's linearisation, a column per tet (13 by #T): rows 0-11 g = dV/dx on the tet's
/// four nodes, node after node (m^2), row 12 c = kappa / V0 (Pa/m^3). The tet's stiffness block
/// is c g g^T (N/m).
using VolumeBlocks = Eigen::Matrix<double, 13, Eigen::Dynamic>;

/// Each node's tets: entries tet * 4 + (the node's place in the tet, 0-3), in tet order.
struct TetIncidence {
  std::vector<int> start;  ///< #V + 1
  std::vector<int> entries;

  TetIncidence() = default;
  TetIncidence(const Eigen::Matrix4Xi& tets, Eigen::Index nodeCount);
};

class TetStiffnessProduct {
 public:
  static constexpr int kParts = BlockLinearOperator::kParts;
  using PartBounds = BlockLinearOperator::PartBounds;

  TetStiffnessProduct(const Eigen::Matrix4Xi& tets, const PartBounds& bounds);

  const PartBounds& bounds() const { return m_bounds; }

  /// Rows of part p's nodes: y += K x (K from `blocks`, 13 by #T).
  void addPart(int part, const VolumeBlocks& blocks, const double* x, double* y) const;

 private:
  /// A tet as the product reads it: where its nodes' rows start, its index, and which of its
  /// nodes (bit i: node i) lie in the part that lists it.
  struct Entry {
    std::array<int, 4> rows;
    int tet;
    unsigned ownNodes;
  };
  /// The tets [begin, end) of m_entries into y; AllOwn: every node of each is the part's.
  template <bool AllOwn>
  void addRange(std::size_t begin, std::size_t end, const double* blocks, const double* x,
                double* y) const;

  PartBounds m_bounds;
  // Per part, its tets in two lists (all four nodes its own; some), m_listStart[p] = {all, some,
  // end} into m_entries.
  std::vector<Entry> m_entries;
  std::array<std::array<std::size_t, 3>, kParts> m_listStart{};
};

}  // namespace tissuesim
