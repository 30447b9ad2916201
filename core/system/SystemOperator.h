// SPDX-License-Identifier: Apache-2.0
#pragma once
// Newton's linear system, applied without assembling it (matrix-free):
//
//   A = sum_f K_f + diag(d_j I),   d_j = w m_j + s                                       (N/m)
//
// K_f each force field's stiffness at the Newton iterate (its current slot: forces/ForceField.h),
// d_j node j's inertia weight w (1/s^2) times its mass and a Levenberg-Marquardt shift s (N/m);
// the fixed DOFs' rows and columns are the identity's. A: 3#V by 3#V; x, y: 3#V.
//
// Parallel parts: kParts node ranges of about equal product work (the fields say what each node
// costs). Each field adds its rows of part p alone, in a fixed order, so products are
// bit-identical for any thread count.
//
// The product's precondition: x is zero on the fixed DOFs (CG's directions are, since its
// right-hand side and preconditioner are), so the fixed columns need no masking; the fixed rows
// of y are x's. No allocation once constructed.

#include <vector>

#include <Eigen/Core>

#include "numerics/BlockLinearOperator.h"
#include "system/MechanicalSystem.h"

namespace tissuesim {

class SystemOperator final : public BlockLinearOperator {
 public:
  /// The operator of `system`'s fields (prepares their products on its node ranges). The
  /// system must outlive this object. Throws std::invalid_argument when 3#V overflows an int.
  explicit SystemOperator(MechanicalSystem& system);

  /// d_j = massWeight m_j + shift (N/m): massWeight (1/s^2), shift (N/m).
  void setDiagonal(double massWeight, double shift_N_m) {
    m_massWeight = massWeight;
    m_shift_N_m = shift_N_m;
  }
  /// 3#V flags; the per-part lists are rebuilt only when the flags change.
  void setFixedDofs(const std::vector<char>& isFixed);

  Eigen::Index nodeCount() const override { return m_mass_kg.size(); }
  const PartBounds& partBounds() const override { return m_bounds; }
  void multiplyPart(int part, const double* x, double* y) const override;
  Eigen::Matrix3d diagonalBlock(Eigen::Index j) const override;
  /// The fields' preconditioner blocks (ForceField::addPreconditionerBlock) with the mass's.
  Eigen::Matrix3d preconditionerBlock(Eigen::Index j) const override;

  /// The largest diagonal entry of A (N/m; a scale for Levenberg-Marquardt shifts). A pass
  /// over the fields: not for every iteration.
  double largestDiagonalEntry() const;

 private:
  using AddBlock = void (ForceField::*)(Eigen::Index, Eigen::Matrix3d&) const;
  /// The mass's block and every field's addBlock at node j, each fixed DOF's row and column
  /// then those of the identity.
  Eigen::Matrix3d sumOfBlocks(Eigen::Index j, AddBlock addBlock) const;
  const Eigen::VectorXd& m_mass_kg;
  std::vector<const ForceField*> m_fields;
  PartBounds m_bounds{};
  double m_massWeight = 0.0;
  double m_shift_N_m = 0.0;
  std::vector<char> m_isFixed;            ///< 3#V, as last set
  std::vector<Eigen::Index> m_fixedDofs;  ///< the fixed DOFs, part after part
  std::array<std::size_t, kParts + 1> m_fixedStart{};
};

}  // namespace tissuesim
