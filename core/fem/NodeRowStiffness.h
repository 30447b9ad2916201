// SPDX-License-Identifier: Apache-2.0
#pragma once
// A field's stiffness kept by node rows of 3x3 blocks, as an assembled matrix keeps it: node j's
// neighbours (j among them, sorted) at neighbours.nodes[start[j] .. start[j + 1]), and the block
// K_(j n) (N/m, column-major) of each in a slot's column of the same index:
//
//   (K x)_j = sum over j's neighbours n of K_(j n) x_n                (x, K x: 3#V; m, N)
//
// Why rows: a product element by element reads each element's whole matrix once per node of it
// (a tet's 12x12, a face cell's 9x9 tangent and its 4 or 5 gradients); by rows it reads each
// block once. The elements' own passes gather their blocks into the rows, node range by node
// range in a fixed order, so the rows are bit-identical for any thread count.
//
// Two slots, the force passes' current and trial (forces/ForceField.h); products, diagonal
// blocks and assembly read the current one.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "forces/ForceField.h"
#include "mesh/TetMesh.h"

namespace tissuesim {

class NodeRowStiffness {
 public:
  using Blocks = Eigen::Matrix<double, 9, Eigen::Dynamic>;  ///< a 3x3 block a column

  NodeRowStiffness() = default;
  explicit NodeRowStiffness(NodeStars neighbours);

  /// The column of K_(j n) (n must be one of j's neighbours).
  int entry(int j, int n) const { return starEntry(m_neighbours, j, n); }

  /// The slot a pass asking for `which` (Current or Trial) writes.
  Blocks& slot(StiffnessSlot which) const {
    return m_slots[static_cast<std::size_t>(which == StiffnessSlot::Trial ? 1 - m_current
                                                                          : m_current)];
  }
  void acceptTrial() const { m_current = 1 - m_current; }
  /// Node j's row of `blocks` set to zero, for a pass to gather into.
  void clearRow(Blocks& blocks, Eigen::Index j) const;

  /// nodeWork[j] += 9 a block of j's row.
  void addProductWork(std::vector<Eigen::Index>& nodeWork) const;
  /// Rows first <= j < last of y += K x (the current slot).
  void addProduct(Eigen::Index first, Eigen::Index last, const double* x, double* y) const;
  void addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const;
  void addStiffness(NodeBlockMatrix& matrix) const;

 private:
  const Blocks& current() const { return m_slots[static_cast<std::size_t>(m_current)]; }

  NodeStars m_neighbours;
  mutable std::array<Blocks, 2> m_slots;
  mutable int m_current = 0;
};

/// Each node's neighbours through cells of nodes (cell c's at nodes[start[c] .. start[c + 1])):
/// the nodes of the cells that hold it, itself among them, sorted; a node in no cell has itself
/// alone.
NodeStars cellNeighbours(const std::vector<int>& start, const std::vector<int>& nodes,
                         Eigen::Index nodeCount);

}  // namespace tissuesim
