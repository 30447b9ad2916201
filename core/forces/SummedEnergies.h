// SPDX-License-Identifier: Apache-2.0
#pragma once
// Several energies added to the FEM's own as one (FemExtraEnergy): the probe's contact forces,
// the body's weight and a tray, say. E = sum_i E_i, and so its gradient and Hessian.

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "forces/FemExtraEnergy.h"

namespace tissuesim {

/// Several energies added to the FEM's as one (null entries skipped); they must outlive it.
class SummedEnergies final : public FemExtraEnergy {
 public:
  std::vector<const FemExtraEnergy*> terms;

  double add(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient,
             std::vector<Eigen::Triplet<double>>* hessian) const override {
    double energy = 0.0;
    for (const FemExtraEnergy* term : terms) {
      if (term != nullptr) energy += term->add(x, gradient, hessian);
    }
    return energy;
  }
};

}  // namespace tissuesim
