// SPDX-License-Identifier: Apache-2.0
#pragma once
// Checks shared by the force fields' tests: a field's K assembled at a state, and -df/dx by
// central differences of its forces, both as dense 3#V-square matrices; a field's passes on a
// pool against its serial ones.

#include <Eigen/Core>

#include <gtest/gtest.h>

#include "forces/ForceField.h"
#include "numerics/NodeBlockMatrix.h"
#include "parallel/ForkJoinPool.h"

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

/// A force pass (forces, stiffness into the current slot, the explicit bound) and a product with
/// `direction` at x on fields made by `make()` with pools of 1, 2 and 3 threads give the bits of
/// the serial field's; `sameReport(pooled, serial)` compares the passes' reports.
template <typename MakeField, typename SameReport>
void expectPoolPassesBitIdentical(const MakeField& make, const Eigen::Matrix3Xd& x,
                                  const Eigen::Matrix3Xd& direction, const SameReport& sameReport) {
  const auto serial = make();
  ForcePass pass;
  pass.stiffness = StiffnessSlot::Current;
  Eigen::VectorXd expectedBound = Eigen::VectorXd::Zero(x.cols());
  pass.nodeStiffness = &expectedBound;
  Eigen::Matrix3Xd expected = Eigen::Matrix3Xd::Zero(3, x.cols());
  ForceReport expectedReport;
  serial.addForces(x, expected, pass, expectedReport);
  const double* v = direction.data();
  Eigen::VectorXd expectedProduct = Eigen::VectorXd::Zero(x.size());
  for (int part = 0; part < ForceField::kParts; ++part)
    serial.addStiffnessProduct(part, v, expectedProduct.data());
  ASSERT_GT(expectedBound.minCoeff(), 0.0);
  for (const int threads : {1, 2, 3}) {
    ForkJoinPool pool(threads);
    auto pooled = make();
    pooled.setThreadPool(&pool);
    Eigen::VectorXd bound = Eigen::VectorXd::Zero(x.cols());
    pass.nodeStiffness = &bound;
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
    ForceReport report;
    pooled.addForces(x, f, pass, report);
    EXPECT_EQ(f, expected) << threads << " threads";
    EXPECT_EQ(bound, expectedBound) << threads << " threads";
    EXPECT_TRUE(sameReport(report, expectedReport)) << threads << " threads";
    Eigen::VectorXd product = Eigen::VectorXd::Zero(x.size());
    pool.run(ForceField::kParts,
             [&](int part) { pooled.addStiffnessProduct(part, v, product.data()); });
    EXPECT_EQ(product, expectedProduct) << threads << " threads";
  }
}

}  // namespace tissuesim::test
