// SPDX-License-Identifier: Apache-2.0
#pragma once
// The tissue as a finite-element continuum on the simulator's own tet mesh: the isochoric
// energy W_T(I1bar) of the tissue file (StrainEnergy, Eqs. 2-9) in each linear tet, with the
// volume term per lattice cube (VolumeForceField) as its volumetric part. Together they are a
// mean-dilatation element (one pressure per cube, as Q1/P0): linear tets alone would lock under
// near-incompressibility, but I1bar = J^(-2/3) tr(C) does not change with volume, so the
// isochoric part is free of it and the cube's J carries all of the volume.
//
//   E = sum_t V0_t W_T(I1bar(F_t)),   F_t = sum_a x_a g_a^T                               (J)
//   f_a = -V0_t P g_a,   P = dW/dF (IsochoricMaterialPoint.h)                              (N)
//   K_ab = V0_t sum_JL dP_iJ/dF_kL g_aJ g_bL                                        (N/m, 3x3)
//
// g_a (1/m) is the gradient of tet t's shape function a at rest; F is constant in the tet.
// Where the pass asks for K's PSD projection (CG), dP/dF's 9x9 is projected (its negative
// eigenvalues set to zero), so each K_t is PSD.
//
// Past the chain model's usable range (r > 1 - kLockingMargin) W_T is continued linearly in
// I1bar from its last value, so a tet driven past locking still gets a finite restoring force
// (counted in the report, as the springs count theirs). A tet with J <= 0 has no I1bar: it adds
// nothing here and is counted as inverted; the cube's volume term pushes it back.
//
// Passes: the tets in four fixed ranges (on the pool when one is set) each write their own
// forces and K_t; then each node gathers its tets' in a fixed order: bit-identical results for
// any thread count. K is kept by node rows of 3x3 blocks (as an assembled matrix's), so a
// product reads each node's neighbours once rather than each of its tets' 12x12. Nothing in a
// pass allocates.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "fem/NodeRowStiffness.h"
#include "forces/ForceField.h"
#include "material/StrainEnergy.h"
#include "mesh/TetMesh.h"
#include "parallel/ForkJoinPool.h"

namespace tissuesim {

class TetIsochoricForceField final : public ForceField {
 public:
  /// @param restPositions_m 3 by #V; @param tets 4 by #T, positively oriented at rest;
  /// `energy` must outlive this object.
  TetIsochoricForceField(const Eigen::Matrix3Xd& restPositions_m, const Eigen::Matrix4Xi& tets,
                         const StrainEnergy& energy);

  void setThreadPool(ForkJoinPool* pool) { m_pool = pool; }

  const char* name() const override { return "isochoric tets"; }
  double energy(const Eigen::Matrix3Xd& x) const override;
  void addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f, const ForcePass& pass,
                 ForceReport& report) const override;
  void acceptTrialStiffness() const override { m_rows.acceptTrial(); }
  void addProductWork(std::vector<Eigen::Index>& nodeWork) const override;
  void addStiffnessProduct(int part, const double* x, double* y) const override;
  void prepareProducts(const PartBounds& bounds) override { m_bounds = bounds; }
  void addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const override;
  void addStiffness(NodeBlockMatrix& matrix) const override;

  Eigen::Index tetCount() const { return m_tets.cols(); }

 private:
  static constexpr int kTetRanges = 4;
  using TetStiffness = Eigen::Matrix<double, 144, Eigen::Dynamic>;  // 12x12 column-major a tet

  /// F of tet t at positions x.
  Eigen::Matrix3d deformationGradient(const Eigen::Matrix3Xd& x, Eigen::Index t) const;

  Eigen::Matrix4Xi m_tets;
  const StrainEnergy& m_energy;
  double m_limitShift = 0.0;  ///< I1bar - 3 at the end of the usable range
  Eigen::Matrix<double, 12, Eigen::Dynamic> m_gradients;  ///< g_a of each tet (1/m)
  Eigen::VectorXd m_restVolume_m3;
  NodeTetIncidence m_tetsOfNode;     ///< entries: 4 t + a for each tet t that holds the node as a
  NodeRowStiffness m_rows;           ///< K by node rows: each node's neighbours through its tets
  std::vector<int> m_incidenceSlot;  ///< 4 per incidence: the row entry of the tet's node n
  ForkJoinPool* m_pool = nullptr;
  PartBounds m_bounds{};

  // Scratch of the passes, sized at construction.
  mutable Eigen::Matrix<double, 12, Eigen::Dynamic> m_tetForces_N;
  mutable TetStiffness m_tetStiffness;  ///< the pass's K_t, gathered into m_rows
  mutable std::array<int, kTetRanges> m_partBeyondRange{};
  mutable std::array<int, kTetRanges> m_partInverted{};
};

}  // namespace tissuesim
