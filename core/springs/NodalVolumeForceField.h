// SPDX-License-Identifier: Apache-2.0
#pragma once
// The near-incompressibility term per node, for tet meshes that are not lattices (Gmsh's, graded
// towards where the tool works): the average nodal pressure tet of Bonet and Burton (1998). Each
// node a owns a quarter of each of its tets, and its dilatation is that share's:
//
//   V_a = sum over a's tets t of V_t / 4,   V0_a likewise at rest,   J_a = V_a / V0_a
//   E_a = 1/2 kappa V0_a (J_a - 1)^2                                                      (J)
//   f = -sum_a p_a g_a,   p_a = kappa (J_a - 1) (Pa),   g_a = dV_a/dx = sum_t dV_t/dx / 4
//     = -sum_t pbar_t dV_t/dx,   pbar_t = the mean of its four nodes' p_a                  (N)
//   K ~= sum_a (kappa / V0_a) g_a g_a^T   (Gauss-Newton: PSD), exact: + sum_t pbar_t d2V_t/dx2
//
// Why per node: on an unstructured mesh the lattice's cube cells (VolumeForceField, one pressure
// per cube as Q1/P0) have no counterpart, and a cell per linear tet locks (about six volume
// constraints per node against three DOFs). One constraint per node leaves three DOFs for it, so
// linear tets under a nearly incompressible tissue no longer lock. g_a spans node a's star (its
// tets' nodes), so K couples nodes two edges apart: the system's matrix takes those couplings
// (couplings()).
//
// U's form is VolumeForceField's (finite through J = 0, so an inverted tet is pushed back); the
// report's ratios are the nodes' J, its inverted count each tet's.
//
// Passes: the tets in kParts fixed ranges compute V_t and dV_t/dx (on the pool when one is set);
// then node ranges gather each node's V_a, J_a, p_a and g_a, and then each node's force from the
// stars it lies in, in a fixed order: bit-identical for any thread count, and no two threads
// write one node. A product computes s_a = k_a g_a . x for each star its part's nodes lie in, in
// that part's own scratch. Nothing in a pass allocates.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "forces/ForceField.h"
#include "mesh/TetMesh.h"
#include "parallel/ForkJoinPool.h"
#include "parallel/NodeRanges.h"

namespace tissuesim {

class NodalVolumeForceField final : public ForceField {
 public:
  static constexpr int kTetRanges = 4;

  /// @param restPositions_m 3 by #V; @param tets 4 by #T, positively oriented at rest (throws
  /// std::invalid_argument otherwise); @param bulkModulus_Pa kappa > 0.
  NodalVolumeForceField(const Eigen::Matrix3Xd& restPositions_m, const Eigen::Matrix4Xi& tets,
                        double bulkModulus_Pa);

  void setThreadPool(ForkJoinPool* pool) { m_pool = pool; }
  double bulkModulus() const { return m_bulkModulus_Pa; }
  const char* name() const override { return "nodal volume"; }
  double energy(const Eigen::Matrix3Xd& x) const override;
  void addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f, const ForcePass& pass,
                 ForceReport& report) const override;
  void acceptTrialStiffness() const override { m_current ^= 1; }
  void addProductWork(std::vector<Eigen::Index>& nodeWork) const override;
  void prepareProducts(const PartBounds& bounds) override;
  void addStiffnessProduct(int part, const double* x, double* y) const override;
  void addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const override;
  void addStiffness(NodeBlockMatrix& matrix) const override;
  /// The node pairs (a < b) that share a star.
  Eigen::Matrix2Xi couplings() const override;

 private:
  /// What K at a state needs: each star entry's g_a (3 by #entries, m^2), each node's p_a, and
  /// whether the exact Hessian was asked for (then the positions, for d2V_t/dx2).
  struct Slot {
    Eigen::Matrix3Xd starGradient_m2;
    Eigen::VectorXd pressure_Pa;
    bool isExact = false;
    Eigen::Matrix3Xd positions_m;
  };
  const Slot& currentSlot() const { return m_slots[static_cast<std::size_t>(m_current)]; }

  Eigen::Matrix4Xi m_tets;
  double m_bulkModulus_Pa;
  ForkJoinPool* m_pool = nullptr;
  Eigen::VectorXd m_inverseNodeRestVolume_1_m3;  ///< #V, 1 / V0_a
  // Node a's star: its nodes (sorted, a among them) at m_stars.nodes[start[a] .. start[a + 1]).
  // m_mirror[e]: for entry e (node b in a's star), the entry of a in b's.
  NodeStars m_stars;
  std::vector<int> m_mirror;
  // Node a's tets: 4 t + (a's corner in t), in tet order.
  NodeTetIncidence m_tetsOfNode;
  /// For tet t, corner c's star entry of corner n at (4 c + n, t).
  Eigen::Matrix<int, 16, Eigen::Dynamic> m_tetStarEntry;

  // Scratch of the const passes, sized at construction.
  mutable Eigen::VectorXd m_tetVolume_m3;                              ///< #T
  mutable Eigen::Matrix<double, 12, Eigen::Dynamic> m_tetGradient_m2;  ///< dV_t/dx, 12 by #T
  mutable std::array<int, kTetRanges> m_partInverted{};
  mutable std::array<VolumeFieldReport, kNodeRanges> m_rangeReport{};
  mutable Eigen::VectorXd m_gradientNorm_m2;  ///< #V, |g_a| (for the explicit integrator's bound)
  mutable std::array<Slot, 3> m_slots;  ///< current, trial; the third for a pass that keeps none
  mutable int m_current = 0;
  // Products: each part's nodes' stars' centres (sorted), and their s_a (#V each, by node).
  PartBounds m_bounds{};
  std::array<std::vector<int>, kParts> m_partStars;
  mutable std::array<Eigen::VectorXd, kParts> m_partProjection;
};

}  // namespace tissuesim
