// SPDX-License-Identifier: Apache-2.0
#pragma once
// The interface through which an energy joins the FEM reference's own (fem/FemModel.h) on the
// same nodes, with its gradient and its assembled Hessian: a rigid tool's penalty, say
// (forces/CapsulePenalty.h). Here, below both, so that a force can serve the spring network
// (ForceField) and the FEM alike without forces/ depending on fem/.
//
// Shapes: x 3 by #V (m); gradient 3 by #V (N); Hessian triplets in the 3#V DOF numbering (N/m).

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace tissuesim {

/// An energy added to the FEM's on the same nodes (a rigid tool's penalty, say).
class FemExtraEnergy {
 public:
  virtual ~FemExtraEnergy() = default;
  /// E at x (J); gradient += dE/dx and hessian += d^2E/dx^2 (3#V DOF numbering) where given.
  virtual double add(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient,
                     std::vector<Eigen::Triplet<double>>* hessian) const = 0;

 protected:
  FemExtraEnergy() = default;
  FemExtraEnergy(const FemExtraEnergy&) = default;
  FemExtraEnergy& operator=(const FemExtraEnergy&) = default;
};

}  // namespace tissuesim
