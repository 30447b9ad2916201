// SPDX-License-Identifier: Apache-2.0
#pragma once
// One force of the mechanical system, as SOFA separates them (its ForceField: addForce,
// addDForce, addKToMatrix): the springs, the volume term, the contacts, gravity. The system
// sums them; Newton's operator and the assembled matrix read their stiffness through this
// interface alone, so a new force (an FEM, friction) needs no change to the solvers.
//
//   E(x) (J),   f(x) = -dE/dx (N, 3 by #V),   K(x) = -df/dx (N/m, 3#V by 3#V, symmetric)
//
// A force pass evaluates f at x and, when asked, keeps what K at x needs (its linearisation) in
// one of two slots: the Newton iterate's (Current) or a line-search trial's (Trial), which
// acceptTrialStiffness() makes current, so an accepted trial's pass serves the next iteration.
// Products, diagonal blocks and assembly read the current slot. K may be the PSD projection of
// the Hessian (each field says how it projects) or the exact Hessian, as the pass asks.
//
// The passes are const: the slots are the fields' scratch, sized at construction (or at
// prepareProducts()), so a step allocates nothing.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "forces/ForceReport.h"
#include "numerics/BlockLinearOperator.h"

namespace tissuesim {

class NodeBlockMatrix;

enum class StiffnessSlot { None, Current, Trial };

struct ForcePass {
  StiffnessSlot stiffness = StiffnessSlot::None;  ///< where K at x goes; None: forces only
  bool isProjected = true;  ///< K's PSD projection (for CG), else the exact Hessian
  /// 3#V flags of the fixed DOFs (the system's): a field that stores K in a reduced form
  /// (the contacts' rank-one terms) zeroes them there. Null: none fixed.
  const std::vector<char>* fixedDofs = nullptr;
  /// When set (#V, N/m): += a bound on each node's row of K, sum of ||K_e|| over the elements
  /// that touch it: the explicit integrator's stability bound, in the same pass.
  Eigen::VectorXd* nodeStiffness = nullptr;
};

class ForceField {
 public:
  using PartBounds = BlockLinearOperator::PartBounds;
  static constexpr int kParts = BlockLinearOperator::kParts;

  virtual ~ForceField() = default;

  virtual const char* name() const = 0;

  /// E(x) (J), for checks of energy behaviour: not for the step loop.
  virtual double energy(const Eigen::Matrix3Xd& x) const = 0;

  /// f += this field's forces at x; K at x into pass.stiffness's slot; `report` gets what the
  /// pass saw (its own part only).
  virtual void addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f, const ForcePass& pass,
                         ForceReport& report) const = 0;

  /// The trial slot becomes the current one (and the current one the next trial's scratch).
  virtual void acceptTrialStiffness() const {}

  /// nodeWork[j] += the work node j's rows of a product cost (entries read): how the operator
  /// cuts its node ranges.
  virtual void addProductWork(std::vector<Eigen::Index>& nodeWork) const { (void)nodeWork; }
  /// Before products on these node ranges (bounds[kParts] = #V): the per-range lists.
  /// Allocates; a second call with the same bounds does nothing.
  virtual void prepareProducts(const PartBounds& bounds) { (void)bounds; }
  /// Rows 3j .. 3j+2 of y += K x for part p's nodes j only (x, y: 3#V). Thread-safe across
  /// different parts; bit-identical whatever thread runs which part.
  virtual void addStiffnessProduct(int part, const double* x, double* y) const = 0;
  /// block += K's (j, j) block.
  virtual void addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const = 0;
  /// block += what CG's block-Jacobi preconditioner takes for K's (j, j) block: that block
  /// itself, unless a field's couplings are better served by weighing it (VolumeForceField).
  virtual void addPreconditionerBlock(Eigen::Index j, Eigen::Matrix3d& block) const {
    addDiagonalBlock(j, block);
  }
  /// matrix += K (its pattern: the system's makeMatrix()).
  virtual void addStiffness(NodeBlockMatrix& matrix) const = 0;
  /// The node pairs K couples beyond the mesh's springs (2 by #P, each pair once, either
  /// order; springs among them are fine): what the system's matrix adds to its pattern.
  virtual Eigen::Matrix2Xi couplings() const { return Eigen::Matrix2Xi(2, 0); }

 protected:
  ForceField() = default;
  ForceField(const ForceField&) = default;
  ForceField& operator=(const ForceField&) = default;
};

/// matrix += `field`'s K at x (its PSD projection when `isProjected`): one force pass into the
/// field's current slot (the passes' scratch, as any pass that asks for stiffness), then its
/// assembly. `forces` (3 by #V) is the pass's scratch; `fixedDofs` as ForcePass's. For set-up and
/// rare refactorisations: a step's solves read K through the products.
void addStiffnessAt(const ForceField& field, const Eigen::Matrix3Xd& x, bool isProjected,
                    NodeBlockMatrix& matrix, Eigen::Matrix3Xd& forces,
                    const std::vector<char>* fixedDofs = nullptr);

}  // namespace tissuesim
