// SPDX-License-Identifier: Apache-2.0
#pragma once
// The tissue's isochoric energy in smoothing cells instead of tets: the smoothed finite element
// on linear tets, each cell's strain the mean of its tets' over its share (StrainCells.h):
//
//   E = sum_c V0_c W_T(I1bar(F_c)),   F_c = sum over c's nodes b of x_b G_cb^T              (J)
//   f_b = -sum over the cells c that hold b of V0_c P_c G_cb,   P = dW/dF                   (N)
//   K_bd = sum_c V0_c sum_JL T_c,(iJ)(kL) G_cb,J G_cd,L,   T = dP/dF (9 by 9)       (N/m, 3x3)
//
// Why: a displacement FEM of linear tets (TetIsochoricForceField) is too stiff, and under a probe
// a few tets wide it stays too stiff until the mesh is far finer there than a real-time step
// affords (docs/performance-details.md, "A volume per node, and the FEM on meshes conformal to
// the organ"). Taking the strain over cells that straddle the tets softens it: per face (FS-FEM)
// the element is softer than the tets' and stiffer than per node (NS-FEM), whose strain energy
// bounds the exact one from the other side (Liu et al. 2009). The volume per node
// (NodalVolumeForceField) is NS-FEM's volumetric part, so with it the pair is the selective
// smoothed FEM for nearly incompressible solids (isochoric part per face, volumetric per node).
//
// T is the exact tangent (IsochoricMaterialPoint.h) or, where the pass asks for K's PSD
// projection (CG), its projection, so each cell's term is PSD. Past the usable range W_T is
// continued linearly (the cell counted in the report's tets.beyondRangeCount); a cell whose F_c
// has det <= 0 adds nothing and is counted in tets.invertedCount; the volume term pushes it back.
//
// Passes: cell ranges compute each cell's F_c, V0_c P_c and, when asked, V0_c T_c; then node
// ranges gather each node's force from the cells that hold it and, when asked, its row of K
// (NodeRowStiffness.h: a face cell's node meets about 15 others, where a product cell by cell
// applied each of its 8 to 12 cells' 9x9 tangent and gradients). Bit-identical for any thread
// count; nothing in a pass allocates.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "fem/NodeRowStiffness.h"
#include "fem/StrainCells.h"
#include "forces/ForceField.h"
#include "material/StrainEnergy.h"
#include "parallel/ForkJoinPool.h"
#include "parallel/NodeRanges.h"

namespace tissuesim {

class SmoothedStrainForceField final : public ForceField {
 public:
  /// @param cells over nodes 0 .. nodeCount - 1 (StrainCells.h); `energy` must outlive this object.
  SmoothedStrainForceField(StrainCells cells, Eigen::Index nodeCount, const StrainEnergy& energy);

  void setThreadPool(ForkJoinPool* pool) { m_pool = pool; }
  const StrainCells& cells() const { return m_cells; }

  const char* name() const override { return "smoothed strain"; }
  double energy(const Eigen::Matrix3Xd& x) const override;
  void addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f, const ForcePass& pass,
                 ForceReport& report) const override;
  void acceptTrialStiffness() const override { m_rows.acceptTrial(); }
  void addProductWork(std::vector<Eigen::Index>& nodeWork) const override;
  void prepareProducts(const PartBounds& bounds) override { m_bounds = bounds; }
  void addStiffnessProduct(int part, const double* x, double* y) const override;
  void addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const override;
  void addStiffness(NodeBlockMatrix& matrix) const override;
  /// The node pairs (a < b) that share a cell.
  Eigen::Matrix2Xi couplings() const override;

 private:
  /// F_c at positions x.
  Eigen::Matrix3d deformationGradient(const Eigen::Matrix3Xd& x, Eigen::Index c) const;
  /// += cell c's blocks of entry e's node's row of K (the pass's tangents).
  void addCellRow(Eigen::Index c, int e, NodeRowStiffness::Blocks& rowBlocks) const;

  StrainCells m_cells;
  const StrainEnergy& m_energy;
  double m_limitShift = 0.0;  ///< I1bar - 3 at the end of the usable range
  // Node j's entries in m_cells.nodes at m_nodeEntries[m_nodeEntryStart[j] .. [j + 1]), in
  // order; m_entryCell[e] the cell of entry e.
  std::vector<int> m_nodeEntryStart;
  std::vector<int> m_nodeEntries;
  std::vector<int> m_entryCell;
  NodeRowStiffness m_rows;  ///< K by node rows: each node's neighbours through its cells
  // For entry e (node b of cell c), the row entry of each of c's nodes in b's row, in c's order,
  // at m_pairSlot[m_pairStart[e] ..].
  std::vector<int> m_pairStart;
  std::vector<int> m_pairSlot;
  PartBounds m_bounds{};
  ForkJoinPool* m_pool = nullptr;

  // Scratch of the const passes, sized at construction.
  mutable Eigen::Matrix<double, 9, Eigen::Dynamic> m_cellStress_N_m2;  ///< V0_c P_c, column-major
  mutable Eigen::VectorXd m_boundScale;  ///< ||V0_c T_c|| ||G_c|| (the explicit bound's)
  mutable Eigen::Matrix<double, 81, Eigen::Dynamic> m_tangents;  ///< the pass's V0_c T_c a cell
  mutable std::array<TetFieldReport, kNodeRanges> m_rangeReport{};
};

}  // namespace tissuesim
