// SPDX-License-Identifier: Apache-2.0
// The tray as an energy the FEM adds to its own (forces/PlanePenalty.h): its gradient is its
// energy's derivative and its Hessian the gradient's, a point above the plane is free, and the
// force it carries is what it pushes the points up with.

#include "forces/PlanePenalty.h"

#include <stdexcept>
#include <vector>

#include <Eigen/SparseCore>

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

/// Five nodes; three points below a tilted plane through the origin (two on triangles, one on a
/// node), one above it.
struct Tray {
  Eigen::Vector3d up = Eigen::Vector3d(0.1, 1.0, -0.2).normalized();
  Eigen::Matrix3Xd x = (Eigen::Matrix3Xd(3, 5) << 0.0, 0.01, 0.0, 0.02, 0.0,  //
                        -0.001, -0.0015, -0.0005, 0.004, -0.002,              //
                        0.0, 0.0, 0.01, 0.01, 0.02)
                           .finished();
  PlanePenalty penalty = PlanePenalty(
      {
          {{0, 1, 2}, Eigen::Vector3d(0.2, 0.3, 0.5), 300.0},
          {{1, 2, 4}, Eigen::Vector3d(0.6, 0.1, 0.3), 500.0},
          {{4, 4, 4}, Eigen::Vector3d(1.0, 0.0, 0.0), 200.0},
          {{3, 3, 3}, Eigen::Vector3d(1.0, 0.0, 0.0), 400.0},  // above the plane
      },
      Eigen::Vector3d(0.1, 1.0, -0.2) * 3.0, 0.0);
};

TEST(PlanePenalty, ItsGradientAndHessianAreItsEnergysDerivatives) {
  Tray tray;
  Eigen::Matrix3Xd gradient = Eigen::Matrix3Xd::Zero(3, 5);
  std::vector<Eigen::Triplet<double>> triplets;
  const double energy = tray.penalty.add(tray.x, &gradient, &triplets);
  EXPECT_GT(energy, 0.0);
  EXPECT_EQ(gradient.col(3), Eigen::Vector3d::Zero()) << "the point above the plane is free";
  Eigen::SparseMatrix<double> hessian(15, 15);
  hessian.setFromTriplets(triplets.begin(), triplets.end());
  const double h = 1e-8;
  for (Eigen::Index d = 0; d < 15; ++d) {
    Eigen::Matrix3Xd plus = tray.x, minus = tray.x;
    plus.data()[d] += h;
    minus.data()[d] -= h;
    Eigen::Matrix3Xd gPlus = Eigen::Matrix3Xd::Zero(3, 5), gMinus = Eigen::Matrix3Xd::Zero(3, 5);
    const double ePlus = tray.penalty.add(plus, &gPlus, nullptr);
    const double eMinus = tray.penalty.add(minus, &gMinus, nullptr);
    EXPECT_NEAR((ePlus - eMinus) / (2 * h), gradient.data()[d], 1e-6 * gradient.norm()) << d;
    const Eigen::VectorXd column = Eigen::Map<const Eigen::VectorXd>(gPlus.data(), 15) -
                                   Eigen::Map<const Eigen::VectorXd>(gMinus.data(), 15);
    EXPECT_LT((column / (2 * h) - Eigen::VectorXd(hessian.col(d))).norm(), 1e-5 * 500.0) << d;
  }
}

TEST(PlanePenalty, CarriesWhatItPushesThePointsUpWith) {
  Tray tray;
  Eigen::Matrix3Xd gradient = Eigen::Matrix3Xd::Zero(3, 5);
  tray.penalty.add(tray.x, &gradient, nullptr);
  const Eigen::Vector3d pushed_N = -gradient.rowwise().sum();
  EXPECT_LT((tray.penalty.support_N(tray.x) - pushed_N).norm(), 1e-12);
  EXPECT_GT(pushed_N.dot(tray.up), 0.0);
  EXPECT_LT((pushed_N - pushed_N.dot(tray.up) * tray.up).norm(), 1e-12) << "along up alone";
  // The deepest point: the node at -2 mm, its depth measured along up.
  EXPECT_NEAR(tray.penalty.maxPenetration_m(tray.x), -tray.up.dot(tray.x.col(4)), 1e-15);
}

TEST(PlanePenalty, RefusesAZeroNormal) {
  EXPECT_THROW(PlanePenalty({}, Eigen::Vector3d::Zero(), 0.0), std::invalid_argument);
  EXPECT_THROW(PlanePenalty({}, Eigen::Vector3d::UnitY(), NAN), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
