// SPDX-License-Identifier: Apache-2.0
#pragma once
// Checks shared by the force fields' tests: a field's K assembled at a state, and -df/dx by
// central differences of its forces, both as dense 3#V-square matrices.

#include <Eigen/Core>

#include "forces/ForceField.h"
#include "numerics/NodeBlockMatrix.h"

namespace tissuesim::test {

/// `field`'s K at x (its PSD projection when `isProjected`, else the exact Hessian), assembled on
/// the pattern of `couplings` (2 by #P node pairs).
inline Eigen::MatrixXd assembledStiffness(const ForceField& field, const Eigen::Matrix3Xd& x,
                                          const Eigen::Matrix2Xi& couplings, bool isProjected) {
  NodeBlockMatrix matrix(x.cols(), couplings);
  matrix.setZero();
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  ForcePass pass;
  pass.stiffness = StiffnessSlot::Current;
  pass.isProjected = isProjected;
  ForceReport report;
  field.addForces(x, f, pass, report);
  field.addStiffness(matrix);
  return Eigen::MatrixXd(matrix.matrix());
}

/// -df/dx at x by central differences of `field`'s forces, `step` (m) each way.
inline Eigen::MatrixXd forceDerivative(const ForceField& field, const Eigen::Matrix3Xd& x,
                                       double step) {
  const auto forces = [&](const Eigen::Matrix3Xd& at) {
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, at.cols());
    ForceReport report;
    field.addForces(at, f, ForcePass{}, report);
    return f;
  };
  Eigen::MatrixXd derivative(x.size(), x.size());
  for (Eigen::Index d = 0; d < x.size(); ++d) {
    Eigen::Matrix3Xd up = x, down = x;
    up.data()[d] += step;
    down.data()[d] -= step;
    const Eigen::Matrix3Xd change = forces(up) - forces(down);
    derivative.col(d) = -Eigen::Map<const Eigen::VectorXd>(change.data(), x.size()) / (2 * step);
  }
  return derivative;
}

}  // namespace tissuesim::test
