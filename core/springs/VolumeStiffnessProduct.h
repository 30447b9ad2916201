// SPDX-License-Identifier: Apache-2.0
#pragma once
// The volume term's part of Newton's matrix-free product, y += K x, with
//
//   K = sum_c k_c g_c g_c^T    (N/m; g_c = dV_c/dx on cell c's nodes, k_c = kappa / V0_c)
//
// read from the force pass's VolumeBlocks: k g (g . x) per cell (VolumeCells.h), no dense block.
//
// Parallel parts: node ranges given by the operator. Part p takes g_c . x once for every cell
// with a node among its own, and adds to those nodes only: no two parts write one row, and each
// row's sum runs in a fixed order, so products are bit-identical for any thread count.

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "numerics/BlockLinearOperator.h"
#include "springs/VolumeCells.h"

namespace tissuesim {

/// The volume term's linearisation, a column per cell (kRows by #C): rows 0-23 g = dV/dx on the
/// cell's node slots, slot after slot (m^2; zero in unused slots), row 24 k = kappa / V0
/// (Pa/m^3). The cell's stiffness block is k g g^T (N/m).
inline constexpr int kVolumeBlockRows = 3 * VolumeCells::kMaxNodes + 1;
using VolumeBlocks = Eigen::Matrix<double, kVolumeBlockRows, Eigen::Dynamic>;

/// Each node's cells: entries cell * kMaxNodes + (the node's slot in the cell), in cell order.
struct CellIncidence {
  std::vector<int> start;  ///< #V + 1
  std::vector<int> entries;

  CellIncidence() = default;
  CellIncidence(const VolumeCells& cells, Eigen::Index nodeCount);
};

class VolumeStiffnessProduct {
 public:
  static constexpr int kParts = BlockLinearOperator::kParts;
  using PartBounds = BlockLinearOperator::PartBounds;

  /// Which loop the product runs: the AVX+FMA one where the CPU has both (numerics/
  /// CpuFeatures.h), or the portable one (what other CPUs run; tests compare the two).
  enum class Kernel { Fastest, Portable };

  VolumeStiffnessProduct(const VolumeCells& cells, const PartBounds& bounds,
                         Kernel kernel = Kernel::Fastest);

  const PartBounds& bounds() const { return m_bounds; }

  /// Rows of part p's nodes: y += K x (K from `blocks`).
  void addPart(int part, const VolumeBlocks& blocks, const double* x, double* y) const;

 private:
  /// A cell as the product reads it: where its nodes' rows start, its index, its node count, and
  /// the slots of those of its nodes that lie in the part that lists it (a list, not a mask: the
  /// product writes them without a branch per node).
  struct Entry {
    std::array<int, VolumeCells::kMaxNodes> rows;
    int cell;
    int nodeCount;
    int ownCount;
    std::array<std::uint8_t, VolumeCells::kMaxNodes> ownSlots;
  };
  /// The cells [begin, end) of m_entries into y; AllOwn: every node of each is the part's.
  template <bool AllOwn>
  void addRange(std::size_t begin, std::size_t end, const double* blocks, const double* x,
                double* y) const;

  PartBounds m_bounds;
  bool m_isAvxFma = false;
  // Per part, its cells in two lists (all nodes its own; some), m_listStart[p] = {all, some,
  // end} into m_entries.
  std::vector<Entry> m_entries;
  std::array<std::array<std::size_t, 3>, kParts> m_listStart{};
};

}  // namespace tissuesim
