// SPDX-License-Identifier: Apache-2.0
// The linear tets' isochoric energy: its forces are its energy's gradient, its exact stiffness
// the forces' derivative and agrees with the FEM's material tangent, its projected stiffness is
// PSD, a homogeneous isochoric stretch has the closed form's energy, and the passes give the same
// bits on one thread as on two.

#include "fem/TetIsochoricForceField.h"

#include <random>

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "fem/IsochoricMaterialPoint.h"
#include "mesh/BlockMesher.h"
#include "numerics/NodeBlockMatrix.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

/// A 2 x 2 x 1 cell block, stretched 15 % along x, squeezed across and jiggled.
struct DeformedBlock {
  TetMesh mesh = makeBlockMesh({0.02, 0.02, 0.01}, {2, 2, 1});
  TetIsochoricForceField field{mesh.nodes_m, mesh.tets, test::liverEnergy()};
  test::DeformedPositions deformed = test::stretchedAndJiggled(mesh.nodes_m, 5, 3e-4);
  Eigen::Matrix3Xd& x = deformed.x;
  Eigen::Matrix3Xd& direction = deformed.direction;

  Eigen::Matrix3Xd forces(const Eigen::Matrix3Xd& at, StiffnessSlot slot = StiffnessSlot::None,
                          bool isProjected = false, ForceReport* report = nullptr) const {
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, at.cols());
    ForcePass pass;
    pass.stiffness = slot;
    pass.isProjected = isProjected;
    ForceReport local;
    field.addForces(at, f, pass, report != nullptr ? *report : local);
    return f;
  }

  /// K v through the matrix-free product, every part.
  Eigen::Matrix3Xd product(const Eigen::Matrix3Xd& v) const {
    Eigen::Matrix3Xd y = Eigen::Matrix3Xd::Zero(3, v.cols());
    for (int part = 0; part < ForceField::kParts; ++part) {
      field.addStiffnessProduct(part, v.data(), y.data());
    }
    return y;
  }
};

TEST(TetIsochoricForceField, TheForcesAreTheEnergysNegativeGradient) {
  const DeformedBlock block;
  const Eigen::Matrix3Xd f = block.forces(block.x);
  constexpr double h = 1e-7;
  const double slope = (block.field.energy(block.x + h * block.direction) -
                        block.field.energy(block.x - h * block.direction)) /
                       (2.0 * h);
  const double expected = -f.cwiseProduct(block.direction).sum();
  ASSERT_GT(std::abs(expected), 1e-3);
  EXPECT_NEAR(slope, expected, 1e-6 * std::abs(expected));
}

TEST(TetIsochoricForceField, TheExactStiffnessIsTheForcesNegativeDerivative) {
  DeformedBlock block;
  block.field.prepareProducts(
      {0, 4, 9, 13, static_cast<Eigen::Index>(block.x.cols())});  // uneven parts on purpose
  (void)block.forces(block.x, StiffnessSlot::Current, /*isProjected=*/false);
  const Eigen::Matrix3Xd kv = block.product(block.direction);
  constexpr double h = 1e-7;
  const Eigen::Matrix3Xd expected =
      -(block.forces(block.x + h * block.direction) - block.forces(block.x - h * block.direction)) /
      (2.0 * h);
  ASSERT_GT(expected.norm(), 1.0);
  EXPECT_LT((kv - expected).norm(), 1e-6 * expected.norm());

  // The diagonal blocks and the assembled matrix are the same K.
  Eigen::Matrix2Xi edges(2, 0);
  for (Eigen::Index t = 0; t < block.mesh.tetCount(); ++t) {
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        edges.conservativeResize(2, edges.cols() + 1);
        edges.col(edges.cols() - 1) << block.mesh.tets(a, t), block.mesh.tets(b, t);
      }
    }
  }
  // Each pair once.
  std::vector<std::pair<int, int>> pairs;
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    pairs.emplace_back(std::min(edges(0, e), edges(1, e)), std::max(edges(0, e), edges(1, e)));
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  Eigen::Matrix2Xi unique(2, static_cast<Eigen::Index>(pairs.size()));
  for (std::size_t e = 0; e < pairs.size(); ++e) {
    unique.col(static_cast<Eigen::Index>(e)) << pairs[e].first, pairs[e].second;
  }
  NodeBlockMatrix matrix(block.x.cols(), unique);
  matrix.setZero();
  block.field.addStiffness(matrix);
  const Eigen::VectorXd assembled =
      matrix.matrix() * Eigen::Map<const Eigen::VectorXd>(block.direction.data(), kv.size());
  EXPECT_LT((assembled - Eigen::Map<const Eigen::VectorXd>(kv.data(), kv.size())).norm(),
            1e-12 * kv.norm());
  const Eigen::MatrixXd dense = matrix.matrix();
  for (Eigen::Index j = 0; j < block.x.cols(); ++j) {
    Eigen::Matrix3d diagonal = Eigen::Matrix3d::Zero();
    block.field.addDiagonalBlock(j, diagonal);
    EXPECT_LT((diagonal - dense.block<3, 3>(3 * j, 3 * j)).norm(), 1e-12 * dense.norm());
  }
}

TEST(TetIsochoricForceField, ItsTangentIsTheMaterialPointsOfTheReferenceFem) {
  // One tet whose shape gradients are the identity's rows: F is then x's columns 1-3 minus
  // column 0, and K's (1..3, 1..3) blocks are V0 dP/dF rearranged.
  Eigen::Matrix3Xd rest(3, 4);
  rest << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  Eigen::Matrix4Xi tets(4, 1);
  tets << 0, 1, 2, 3;
  const TetIsochoricForceField field(rest, tets, test::liverEnergy());
  Eigen::Matrix3d f;
  f << 1.2, 0.05, -0.03, 0.02, 0.93, 0.04, -0.01, 0.03, 0.91;
  Eigen::Matrix3Xd x(3, 4);
  x.col(0).setZero();
  x.rightCols(3) = f;
  Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, 4);
  ForcePass pass;
  pass.stiffness = StiffnessSlot::Current;
  pass.isProjected = false;
  ForceReport report;
  field.addForces(x, forces, pass, report);
  const IsochoricResponse expected = evaluateIsochoric(test::liverEnergy(), f, true);
  ASSERT_TRUE(expected.isAdmissible);
  const double volume = 1.0 / 6.0;
  // f_b = -V0 P g_b with g_b = e_b for b = 1..3: column b - 1 of P.
  EXPECT_LT((forces.rightCols(3) + volume * expected.stress_Pa).norm(),
            1e-10 * expected.stress_Pa.norm());
  // K_(b, c)(i, k) = V0 dP_(i, b-1) / dF_(k, c-1).
  Eigen::Matrix3Xd unit = Eigen::Matrix3Xd::Zero(3, 4);
  for (int c = 1; c < 4; ++c) {
    for (int k = 0; k < 3; ++k) {
      unit.setZero();
      unit(k, c) = 1.0;
      Eigen::Matrix3Xd y = Eigen::Matrix3Xd::Zero(3, 4);
      for (int part = 0; part < ForceField::kParts; ++part) {
        field.addStiffnessProduct(part, unit.data(), y.data());
      }
      for (int b = 1; b < 4; ++b) {
        for (int i = 0; i < 3; ++i) {
          EXPECT_NEAR(y(i, b), volume * expected.tangent_Pa(3 * i + (b - 1), 3 * k + (c - 1)),
                      1e-9 * expected.tangent_Pa.norm());
        }
      }
    }
  }
}

TEST(TetIsochoricForceField, TheClosedFormProjectionIsTheTangentsEigenProjection) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Matrix3d> deformations;
  deformations.push_back(Eigen::Matrix3d::Identity());                      // rest
  deformations.push_back(Eigen::Vector3d(1.3, 0.877, 0.877).asDiagonal());  // equal pair
  deformations.push_back(Eigen::Vector3d(0.8, 1.1, 1.15).asDiagonal());     // compressed
  for (int n = 0; n < 6; ++n) {
    Eigen::Matrix3d f = Eigen::Matrix3d::Identity();
    for (int i = 0; i < 9; ++i) f.data()[i] += 0.25 * uniform(random);
    if (f.determinant() < 0.2) continue;
    deformations.push_back(f);
  }
  ASSERT_GE(deformations.size(), 7U);
  int indefinite = 0;
  for (const Eigen::Matrix3d& f : deformations) {
    const IsochoricResponse exact = evaluateIsochoric(test::liverEnergy(), f, true);
    ASSERT_TRUE(exact.isAdmissible);
    const double scale = std::pow(f.determinant(), -2.0 / 3.0);
    const EnergyInI1 w =
        test::liverEnergy().atInvariantShift(std::max(scale * f.squaredNorm() - 3.0, 0.0));
    const Eigen::SelfAdjointEigenSolver<StressTangent> eigen(exact.tangent_Pa);
    if (eigen.eigenvalues().minCoeff() < -1e-9 * eigen.eigenvalues().maxCoeff()) ++indefinite;
    const StressTangent expected = eigen.eigenvectors() *
                                   eigen.eigenvalues().cwiseMax(0.0).asDiagonal() *
                                   eigen.eigenvectors().transpose();
    const StressTangent projected = projectedIsochoricTangent(f, w.dEnergy, w.d2Energy);
    EXPECT_LT((projected - expected).norm(), 1e-9 * exact.tangent_Pa.norm()) << f;
  }
  EXPECT_GE(indefinite, 2);  // the projection had something to do
}

TEST(TetIsochoricForceField, TheProjectedStiffnessIsPositiveSemiDefinite) {
  DeformedBlock block;
  // Strongly sheared and compressed: the exact Hessian of I1bar is indefinite there.
  block.x.row(0) += 0.8 * block.mesh.nodes_m.row(2);
  block.x.row(2) *= 0.6;
  (void)block.forces(block.x, StiffnessSlot::Current, /*isProjected=*/true);
  Eigen::MatrixXd dense(block.x.size(), block.x.size());
  Eigen::Matrix3Xd unit = Eigen::Matrix3Xd::Zero(3, block.x.cols());
  for (Eigen::Index d = 0; d < block.x.size(); ++d) {
    unit.setZero();
    unit.data()[d] = 1.0;
    const Eigen::Matrix3Xd y = block.product(unit);
    dense.col(d) = Eigen::Map<const Eigen::VectorXd>(y.data(), y.size());
  }
  const Eigen::VectorXd eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense).eigenvalues();
  EXPECT_GT(eigenvalues.minCoeff(), -1e-9 * eigenvalues.maxCoeff());
  (void)block.forces(block.x, StiffnessSlot::Current, /*isProjected=*/false);
  for (Eigen::Index d = 0; d < block.x.size(); ++d) {
    unit.setZero();
    unit.data()[d] = 1.0;
    const Eigen::Matrix3Xd y = block.product(unit);
    dense.col(d) = Eigen::Map<const Eigen::VectorXd>(y.data(), y.size());
  }
  // The test means something: the exact one is not.
  EXPECT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense).eigenvalues().minCoeff(),
            -1e-6 * eigenvalues.maxCoeff());
}

TEST(TetIsochoricForceField, AnIsochoricStretchHasTheClosedFormsEnergy) {
  const TetMesh mesh = makeBlockMesh({0.01, 0.01, 0.01}, {1, 1, 1});
  const TetIsochoricForceField field(mesh.nodes_m, mesh.tets, test::liverEnergy());
  for (const double lambda : {1.0, 1.05, 1.2, 1.35, 0.8}) {
    Eigen::Matrix3Xd x = mesh.nodes_m;
    x.row(0) *= lambda;
    x.bottomRows(2) /= std::sqrt(lambda);
    const double expected = 1e-6 * test::liverEnergy().energy(lambda);
    EXPECT_NEAR(field.energy(x), expected, 1e-15 + 1e-9 * expected) << lambda;
    // A homogeneous deformation leaves interior-free forces: only the boundary nodes pull, and
    // the net force is zero.
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
    ForceReport report;
    field.addForces(x, f, {}, report);
    EXPECT_LT(f.rowwise().sum().norm(), 1e-12 + 1e-9 * f.norm());
  }
}

TEST(TetIsochoricForceField, PastLockingAndInvertedTetsAreCountedAndStayFinite) {
  const TetMesh mesh = makeBlockMesh({0.01, 0.01, 0.01}, {1, 1, 1});
  const TetIsochoricForceField field(mesh.nodes_m, mesh.tets, test::liverEnergy());
  Eigen::Matrix3Xd x = mesh.nodes_m;
  x.row(0) *= 2.5;  // far past lambda 1.5, where the chains lock
  x.bottomRows(2) /= std::sqrt(2.5);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  ForceReport report;
  ForcePass pass;
  pass.stiffness = StiffnessSlot::Current;
  field.addForces(x, f, pass, report);
  EXPECT_EQ(report.tets.beyondRangeCount, mesh.tetCount());
  EXPECT_TRUE(f.allFinite());
  EXPECT_TRUE(std::isfinite(field.energy(x)));
  EXPECT_GT(f.norm(), 0.0);

  x = mesh.nodes_m;
  x.row(2) *= -1.0;  // every tet mirrored
  f.setZero();
  report = {};
  field.addForces(x, f, pass, report);
  EXPECT_EQ(report.tets.invertedCount, mesh.tetCount());
  EXPECT_TRUE(f.allFinite());
}

TEST(TetIsochoricForceField, OneThreadAndTwoGiveTheSameBits) {
  DeformedBlock block;
  const Eigen::Matrix3Xd serial = block.forces(block.x, StiffnessSlot::Current, true);
  const Eigen::Matrix3Xd serialProduct = block.product(block.direction);
  ForkJoinPool pool(2);
  block.field.setThreadPool(&pool);
  const Eigen::Matrix3Xd threaded = block.forces(block.x, StiffnessSlot::Current, true);
  EXPECT_EQ(serial, threaded);
  EXPECT_EQ(serialProduct, block.product(block.direction));
}

}  // namespace
}  // namespace tissuesim
