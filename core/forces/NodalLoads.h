// SPDX-License-Identifier: Apache-2.0
#pragma once
// Constant forces on some nodes, as the energy a static solve minimises with them:
//
//   E(x) = - sum_j f_j . x_{node_j}     (J),   dE/dx_{node_j} = -f_j,   no Hessian
//
// Shapes: forces 3 by #loads (N), one column per entry of nodes.

#include <vector>

#include <Eigen/Core>

#include "forces/FemExtraEnergy.h"

namespace tissuesim {

class NodalLoads final : public FemExtraEnergy {
 public:
  std::vector<int> nodes;
  Eigen::Matrix3Xd forces_N;

  double add(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient,
             std::vector<Eigen::Triplet<double>>*) const override {
    double energy = 0.0;
    for (std::size_t j = 0; j < nodes.size(); ++j) {
      const auto load = forces_N.col(static_cast<Eigen::Index>(j));
      energy -= load.dot(x.col(nodes[j]));
      if (gradient != nullptr) gradient->col(nodes[j]) -= load;
    }
    return energy;
  }
};

}  // namespace tissuesim
