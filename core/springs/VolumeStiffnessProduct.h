// SPDX-License-Identifier: Apache-2.0
#pragma once
// The volume term's part of Newton's matrix-free product, y += K x, with
//
//   K = sum_c k_c g_c g_c^T    (N/m; g_c = dV_c/dx on cell c's nodes, k_c = kappa / V0_c)
//
// read from the force pass's VolumeBlocks: k g (g . x) per cell (VolumeCells.h), no dense block.
//
// Parallel parts: node ranges given by the operator. Part p takes s_c = k_c g_c . x once for
// every cell with a node among its own (its own scratch), then each of its nodes gathers
// sum_c s_c g_c,i over its cells: one write per row, no two parts writing one row or one s_c,
// and each row's sum in a fixed order, so products are bit-identical for any thread count.

#include <array>
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
  /// A cell as the product reads it: where its nodes' rows start, its index, its node count.
  struct Entry {
    std::array<int, VolumeCells::kMaxNodes> rows;
    int cell;
    int nodeCount;
  };
  /// One of a node's cells: its entry (in the node's part) and where its g_i starts in the
  /// blocks (kVolumeBlockRows cell + 3 slot).
  struct Term {
    int entry;
    int offset;
  };

  PartBounds m_bounds;
  bool m_isAvxFma = false;
  // Per part p, its cells: m_entries[m_partStart[p] .. m_partStart[p + 1]).
  std::vector<Entry> m_entries;
  std::array<std::size_t, kParts + 1> m_partStart{};
  // Per node j, its terms: m_terms[m_termStart[j] .. m_termStart[j + 1]), in entry order.
  std::vector<int> m_termStart;
  std::vector<Term> m_terms;
  // k_c (g_c . x) per entry: scratch of the const product, each part writing its own entries.
  mutable std::vector<double> m_scales;
};

}  // namespace tissuesim
