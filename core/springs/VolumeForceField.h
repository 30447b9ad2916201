// SPDX-License-Identifier: Apache-2.0
#pragma once
// The near-incompressibility term, per cell of tets (VolumeCells.h: a lattice cube, else one
// tet; docs/model.md, "The volume term"):
//
//   E_c = 1/2 kappa V0 (J - 1)^2,   J = V / V0,   V = sum over the cell's tets of V_t,
//   V_t = (x_b - x_a) . ((x_c - x_a) x (x_d - x_a)) / 6
//   f_i = -kappa (J - 1) g_i,   g_i = dV/dx_i                                             (N)
//   H_c ~= (kappa / V0) g g^T,  g = dV/dx (3 x the cell's nodes)   (Gauss-Newton: PSD part)
//
// kappa (Pa) is a bulk modulus. Why this form and not a log or barrier in J: the energy and its
// gradient stay finite through J = 0, so a tet that a fast poke has turned inside out is pushed
// back (E grows as J falls below 1, and g does not vanish on a flat tet), where a log(J) term
// has no value past J = 0 and no way back. It is the volumetric part of Smith, de Goes and
// Kim's stable Neo-Hookean energy (2018) at its rest-stable form. The spring network alone has a
// mirrored equilibrium for a flipped tet; with this term a flipped tet takes twice its volume
// from its cell's (a sixth of a cube's: a third of the cube's volume is lost), which the term
// restores, and the inversion check still looks at every tet.
//
// Its stiffness is rank one per cell, so Newton's matrix-free operator applies it as k g (g . x)
// (VolumeStiffnessProduct) from the numbers a cell this pass stores: no dense block.
//
// A cube's term holds the cube's volume, not each of its six tets': under a probe pressed deep
// into a fine lattice one tet can be squeezed flat and through itself while its cube keeps its
// volume (its neighbours take it up). A guard per tet stops that:
//
//   E_t = 1/2 kappa V0_t (J_t - J_g)^2   for J_t = V_t / V0_t < J_g = 1/2, else 0
//   f_i = -kappa (J_t - J_g) g_t,i,   H_t ~= (kappa / V0_t) g_t g_t^T   (one rank-one term)
//
// which only a tet squeezed to half its volume feels. Its few terms are kept beside the cells'
// blocks, as the contacts keep theirs (numerics/RankOneTerm.h). Its modulus is the cells' kappa:
// a stiffer guard's barrier held folds after fast deep pokes that the cells' term undoes
// (docs/scene-file.md, "The guard per tet").
//
// Passes: the cells in kParts fixed ranges compute g, J and the pressure (on the pool when one
// is set); then each node gathers its cells' forces in a node-wise pass, over a node-to-cell
// incidence list in a fixed order. No two threads write one node, and sums run in the same
// order for any thread count: bit-identical results with 1, 2 or 4 threads.

#include <array>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "forces/ForceField.h"
#include "numerics/RankOneTerm.h"
#include "numerics/RankOneTermDiagonals.h"
#include "parallel/ForkJoinPool.h"
#include "springs/SpringMesh.h"
#include "springs/VolumeCells.h"
#include "springs/VolumeStiffnessProduct.h"

namespace tissuesim {

/// d^2V/dx_i dx_j (m) of the signed volume of tet (x_0 .. x_3) = x.col(tet[0 .. 3]), block (i, j)
/// at 4 i + j: symmetric as a whole, each diagonal block zero.
std::array<Eigen::Matrix3d, 16> tetVolumeHessian(const Eigen::Matrix3Xd& x,
                                                 const Eigen::Vector4i& tet);

class VolumeForceField final : public ForceField {
 public:
  static constexpr int kParts = 4;

  /// @param bulkModulus_Pa kappa > 0. `mesh` must outlive this object.
  VolumeForceField(const SpringMesh& mesh, double bulkModulus_Pa);
  ~VolumeForceField() override;

  /// Runs the passes on `pool` (which must outlive this object), or on the caller when null.
  void setThreadPool(ForkJoinPool* pool) { m_pool = pool; }

  /// forces (3 by #V) += volume forces at x; blocks (kVolumeBlockRows by #C) overwritten when
  /// not null. The report's volume ratios are the cells' J (what the term holds), its inverted
  /// count each tet's.
  VolumeFieldReport addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
                              VolumeBlocks* blocks = nullptr) const;
  /// nodeStiffness (#V) += sum over each node's cells of ||H_c|| <= k |g|^2 (N/m), from the last
  /// addForces() pass's blocks: the explicit integrator's stability bound.
  void addNodeStiffnessBound(Eigen::VectorXd& nodeStiffness) const;

  /// Counts tets with J <= 0 at x without computing forces (the ratios: each tet's J, with or
  /// without a volume term); in kInspectParts tet ranges on
  /// `pool` when given (the report is the same: a count and a minimum).
  static VolumeFieldReport inspect(const SpringMesh& mesh, const Eigen::Matrix3Xd& x,
                                   ForkJoinPool* pool = nullptr);
  static constexpr int kInspectParts = 4;

  double bulkModulus() const { return m_bulkModulus_Pa; }
  /// J_g: a tet squeezed below this fraction of its rest volume is pushed back on its own.
  static constexpr double kGuardVolumeRatio = 0.5;
  const VolumeCells& cells() const { return m_cells; }
  const CellIncidence& incidence() const { return m_incidence; }
  const SpringMesh& mesh() const { return m_mesh; }

  // ForceField: the Gauss-Newton K = sum_c k g g^T, PSD, in the products and diagonal blocks
  // (CG's, which asks for the PSD part). The assembled matrix adds the exact Hessian's other
  // part, p d^2V/dx^2 with p = kappa (J - 1), when the pass asked for the exact Hessian: the
  // direct solves of the experiments, where at the FEM's kappa p is as large as the tissue's
  // stress and Newton without it converged only linearly.
  const char* name() const override { return "volume"; }
  /// sum_c E_c at x (J).
  double energy(const Eigen::Matrix3Xd& x) const override;
  void addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f, const ForcePass& pass,
                 ForceReport& report) const override;
  void acceptTrialStiffness() const override { m_current ^= 1; }
  void addProductWork(std::vector<Eigen::Index>& nodeWork) const override;
  void prepareProducts(const PartBounds& bounds) override;
  void addStiffnessProduct(int part, const double* x, double* y) const override;
  void addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const override;
  /// Each cell's part of the diagonal block weighed by sqrt(n), n its node count. Block Jacobi
  /// sees a cell's term k g g^T only through its block diagonal D = diag(k g_i g_i^T), which
  /// matches it for a move of one node (x^T k g g^T x / x^T D x = 1) and underrates it n-fold for
  /// the move it resists most, every node along its g_i (the quotient's largest: Cauchy-Schwarz).
  /// sqrt(n), the two's geometric mean, is about where CG's iterations are fewest on the bundled
  /// liver (docs/performance-details.md, "The volume term's preconditioner"); the solution is
  /// the same, only the path to it shorter.
  void addPreconditionerBlock(Eigen::Index j, Eigen::Matrix3d& block) const override;
  void addStiffness(NodeBlockMatrix& matrix) const override;
  /// The node pairs that share a cell.
  Eigen::Matrix2Xi couplings() const override { return m_cells.nodePairs(); }

 private:
  /// addDiagonalBlock's sum, each cell's part weighed by sqrt(n) when IsWeighed.
  template <bool IsWeighed>
  void addWeightedDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const;
  const VolumeBlocks& currentBlocks() const { return m_slots[static_cast<std::size_t>(m_current)]; }
  /// A whole cube's g (into its slots of gx, gy, gz), its tets counted into `report` and the
  /// guard's list; returns its volume V (m^3).
  double addCubeVolumeGradient(const Eigen::Matrix3Xd& x, Eigen::Index c,
                               std::array<double, VolumeCells::kMaxNodes>& gx,
                               std::array<double, VolumeCells::kMaxNodes>& gy,
                               std::array<double, VolumeCells::kMaxNodes>& gz,
                               VolumeFieldReport& report, std::vector<int>& guarded) const;
  /// The guard (see the header) on the tets the last cell pass listed: forces += its forces at
  /// x, `terms` overwritten with its stiffness, `pressures` with kappa (J_t - J_g) per term.
  void addGuardForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces,
                      std::vector<RankOneTerm>& terms, std::vector<double>& pressures) const;

  const SpringMesh& m_mesh;
  double m_bulkModulus_Pa;
  ForkJoinPool* m_pool = nullptr;
  VolumeCells m_cells;
  CellIncidence m_incidence;
  Eigen::VectorXd m_inverseCellRestVolume_1_m3;  ///< #C, 1 / V0: no division in the pass
  // The stiffness slots (ForceField.h): the current one is m_slots[m_current]. Mutable: scratch
  // of the const passes, sized at construction.
  mutable std::array<VolumeBlocks, 2> m_slots;
  mutable int m_current = 0;
  // The last pass's blocks when the caller keeps none, and its pressures kappa (J - 1) (Pa).
  mutable VolumeBlocks m_ownBlocks;
  // Per slot: whether its pass asked for the exact Hessian, and then its pressures and
  // positions (what addStiffness() needs for p d^2V/dx^2).
  mutable std::array<bool, 2> m_isSlotExact{false, false};
  mutable std::array<Eigen::VectorXd, 2> m_slotPressure_Pa;
  mutable std::array<Eigen::Matrix3Xd, 2> m_slotPositions_m;
  mutable const VolumeBlocks* m_lastBlocks = nullptr;
  mutable Eigen::VectorXd m_pressure_Pa;
  std::unique_ptr<VolumeStiffnessProduct> m_product;  ///< prepareProducts()'s
  // The guard: the tets below J_g that each part of the cell pass found (room for all), and per
  // slot (the third: a pass that keeps no stiffness) its terms, their pressures and diagonals.
  mutable std::array<std::vector<int>, kParts> m_guardedTets;
  std::vector<double> m_guardVolume_m3;  ///< J_g V0_t, in the cells' tet order (read in step)
  mutable std::array<std::vector<RankOneTerm>, 3> m_guardTerms;
  mutable std::array<std::vector<double>, 3> m_guardPressure_Pa;
  mutable std::array<RankOneTermDiagonals, 2> m_guardDiagonals;
  mutable const std::vector<RankOneTerm>* m_lastGuardTerms = nullptr;
};

}  // namespace tissuesim
