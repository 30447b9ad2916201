// SPDX-License-Identifier: Apache-2.0
// The body's weight on quadratic tets (fem/QuadraticTetWeight.h): the consistent loads do the work
// gravity does on any displacement the elements can take, a quadratic one included, and with
// them the FEM's fixed supports carry the whole weight.

#include "fem/QuadraticTetWeight.h"

#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "fem/FemModel.h"
#include "fem/FemStaticSolver.h"
#include "mesh/BlockMesher.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

constexpr double kDensity_kg_m3 = 1060.0;

TEST(QuadraticTetWeight, DoesTheWorkOfGravityOnAQuadraticDisplacement) {
  // u(X) = (X_y^2 + X_x X_z, 0, X_x^2) m, in the quadratic elements' span: the loads' work
  // sum_a f_a . u_a is rho g . integral u dV exactly (a product rule of the block, in closed
  // form). Loads lumped on the corners would get the linear part right and miss this.
  const Eigen::Vector3d size_m(0.02, 0.01, 0.03);
  const QuadraticTetMesh mesh = makeQuadraticTetMesh(makeBlockMesh(size_m, {2, 2, 3}));
  const Eigen::Vector3d g(0.3, -9.81, 1.7);
  const NodalLoads loads = quadraticTetWeight(mesh, kDensity_kg_m3, g);
  ASSERT_EQ(loads.nodes.size(), static_cast<std::size_t>(mesh.nodeCount()));
  Eigen::Vector3d low = mesh.nodes_m.rowwise().minCoeff(), high = mesh.nodes_m.rowwise().maxCoeff();
  ASSERT_LT((high - low - size_m).norm(), 1e-12);
  double work_J = 0.0;
  Eigen::Vector3d total_N = Eigen::Vector3d::Zero();
  for (Eigen::Index a = 0; a < mesh.nodeCount(); ++a) {
    const Eigen::Vector3d p = mesh.nodes_m.col(a) - low;
    const Eigen::Vector3d u(p.y() * p.y() + p.x() * p.z(), 0.0, p.x() * p.x());
    work_J += loads.forces_N.col(a).dot(u);
    total_N += loads.forces_N.col(a);
  }
  const double a = size_m.x(), b = size_m.y(), c = size_m.z();
  const double volume = a * b * c;
  // integral over the box of X_y^2, X_x X_z and X_x^2.
  const Eigen::Vector3d integral(a * c * b * b * b / 3.0 + b * (a * a / 2.0) * (c * c / 2.0), 0.0,
                                 b * c * a * a * a / 3.0);
  EXPECT_LT((total_N - kDensity_kg_m3 * volume * g).norm(), 1e-12 * (kDensity_kg_m3 * volume));
  const double expected_J = kDensity_kg_m3 * g.dot(integral);
  EXPECT_NEAR(work_J, expected_J, 1e-10 * std::abs(expected_J));
}

TEST(QuadraticTetWeight, TheSupportsOfABodyAtBalanceCarryItsWeight) {
  // A block held at its base, hanging under its own weight: Newton settles it, and the forces
  // the fixed nodes exert on it (dE/dx there) add up to its weight, upwards.
  const QuadraticTetMesh mesh = makeQuadraticTetMesh(makeBlockMesh({0.02, 0.02, 0.04}, {2, 2, 4}));
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  const NodalLoads weight = quadraticTetWeight(mesh, kDensity_kg_m3, g);
  FemModel model(mesh, test::liverEnergy(), 200.0 * test::liverEnergy().initialShearModulus());
  model.setExtraEnergy(&weight);
  std::vector<char> isFixed(static_cast<std::size_t>(3 * mesh.nodeCount()), 0);
  for (Eigen::Index a = 0; a < mesh.nodeCount(); ++a) {
    if (mesh.nodes_m(2, a) > 0.04 - 1e-9) std::fill_n(isFixed.begin() + 3 * a, 3, char{1});
  }
  Eigen::Matrix3Xd x = mesh.nodes_m;
  FemStaticSolver solver(1e-9, 50);
  const FemSolveReport report = solver.solve(model, x, isFixed);
  ASSERT_TRUE(report.converged) << report.residual_N;
  EXPECT_LT(x.row(2).minCoeff(), -1e-4) << "it hangs lower than at rest";
  Eigen::Vector3d held_N = Eigen::Vector3d::Zero();
  for (Eigen::Index a = 0; a < mesh.nodeCount(); ++a) {
    if (isFixed[static_cast<std::size_t>(3 * a)] != 0) held_N += solver.gradient().col(a);
  }
  const Eigen::Vector3d weight_N = kDensity_kg_m3 * 0.02 * 0.02 * 0.04 * g;
  EXPECT_LT((held_N + weight_N).norm(), 1e-6 * weight_N.norm()) << held_N.transpose();
}

TEST(QuadraticTetWeight, RefusesADensityThatIsNotPositive) {
  const QuadraticTetMesh mesh = makeQuadraticTetMesh(makeBlockMesh({0.01, 0.01, 0.01}, {1, 1, 1}));
  EXPECT_THROW(quadraticTetWeight(mesh, 0.0, Eigen::Vector3d(0, -9.81, 0)), std::invalid_argument);
  EXPECT_THROW(quadraticTetWeight(mesh, 1000.0, Eigen::Vector3d(0, NAN, 0)), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
