// SPDX-License-Identifier: Apache-2.0
#include "springs/NodalVolumeForceField.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "fem/TetIsochoricForceField.h"
#include "mesh/BlockMesher.h"
#include "mesh/TetMesh.h"
#include "mesh/TetMeshFile.h"
#include "parallel/NodeRanges.h"
#include "springs/StiffnessCouplings.h"
#include "springs/VolumeForceField.h"
#include "support/BlockPress.h"
#include "support/ForceFieldChecks.h"
#include "support/TestMeshes.h"
#include "support/TestSystems.h"
#include "system/NewtonSolver.h"

namespace tissuesim {
namespace {

// The energy from its definition: each node's quarter of its tets' volumes.
double nodalEnergy(const TetMesh& mesh, const Eigen::Matrix3Xd& x, double kappa) {
  Eigen::VectorXd volume = Eigen::VectorXd::Zero(x.cols());
  Eigen::VectorXd rest = Eigen::VectorXd::Zero(x.cols());
  for (Eigen::Index t = 0; t < mesh.tets.cols(); ++t) {
    for (int c = 0; c < 4; ++c) {
      volume[mesh.tets(c, t)] += signedTetVolume(x, mesh.tets, t) / 4;
      rest[mesh.tets(c, t)] += signedTetVolume(mesh.nodes_m, mesh.tets, t) / 4;
    }
  }
  double energy = 0.0;
  for (Eigen::Index a = 0; a < x.cols(); ++a) {
    const double j = volume[a] / rest[a];
    energy += 0.5 * kappa * rest[a] * (j - 1) * (j - 1);
  }
  return energy;
}

TEST(NodalVolumeForceField, ForceIsMinusTheEnergyGradient) {
  const TetMesh mesh = test::unstructuredBlock();
  ASSERT_GT(mesh.tets.cols(), 100);
  const double kappa = 5e4;
  const NodalVolumeForceField field(mesh.nodes_m, mesh.tets, kappa);
  const test::DeformedPositions deformed = test::stretchedAndJiggled(mesh.nodes_m, 3, 4e-4);
  const Eigen::Matrix3Xd& x = deformed.x;
  const double energy = nodalEnergy(mesh, x, kappa);
  ASSERT_GT(energy, 0.0);
  EXPECT_NEAR(field.energy(x), energy, 1e-12 * energy);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  ForceReport report;
  field.addForces(x, f, ForcePass{}, report);
  EXPECT_GT(report.volume.maxVolumeRatio, 1.0);
  EXPECT_LT(report.volume.minVolumeRatio, report.volume.maxVolumeRatio);
  EXPECT_EQ(report.volume.invertedTetCount, 0);
  const double step = 1e-9;
  const double scale = f.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  for (Eigen::Index d = 0; d < x.size(); d += 7) {
    Eigen::Matrix3Xd up = x, down = x;
    up.data()[d] += step;
    down.data()[d] -= step;
    const double gradient =
        (nodalEnergy(mesh, up, kappa) - nodalEnergy(mesh, down, kappa)) / (2 * step);
    EXPECT_NEAR(f.data()[d], -gradient, 1e-6 * scale) << "DOF " << d;
  }
}

TEST(NodalVolumeForceField, TheStiffnessIsTheForcesDerivativeInEveryForm) {
  // Asked for the exact Hessian the assembled matrix is -df/dx; asked for the PSD part it is
  // sum_a k_a g_a g_a^T alone, which the products and diagonal blocks apply too.
  const TetMesh mesh = test::unstructuredBlock();
  const SpringMesh springs = buildSpringMesh(mesh, 1000.0);
  const NodalVolumeForceField field(mesh.nodes_m, mesh.tets, 5e4);
  const test::DeformedPositions deformed = test::stretchedAndJiggled(mesh.nodes_m, 5, 4e-4);
  const Eigen::Matrix3Xd& x = deformed.x;
  const Eigen::Matrix2Xi couplings = stiffnessCouplings(springs, field.couplings());
  const Eigen::MatrixXd exact = test::assembledStiffness(field, x, couplings, false);
  const Eigen::MatrixXd gaussNewton = test::assembledStiffness(field, x, couplings, true);
  const Eigen::MatrixXd differences = test::forceDerivative(field, x, 1e-8);
  const double scale = differences.cwiseAbs().maxCoeff();
  EXPECT_LT((exact - differences).cwiseAbs().maxCoeff(), 1e-6 * scale);
  EXPECT_LT((exact - exact.transpose()).cwiseAbs().maxCoeff(), 1e-12 * scale);
  EXPECT_GT((gaussNewton - differences).cwiseAbs().maxCoeff(), 1e-3 * scale);

  // The explicit integrator's bound on each node's row of K holds the row (its norm, at most).
  Eigen::VectorXd bound = Eigen::VectorXd::Zero(x.cols());
  ForcePass boundPass;
  boundPass.stiffness = StiffnessSlot::Current;
  boundPass.nodeStiffness = &bound;
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  ForceReport report;
  field.addForces(x, f, boundPass, report);
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    const double row = gaussNewton.middleRows<3>(3 * j).norm();
    EXPECT_GE(bound[j], (1 - 1e-12) * row) << "node " << j;
    EXPECT_LT(bound[j], 20.0 * row) << "node " << j;
  }

  // The products and the diagonal blocks read the last pass's slot: the Gauss-Newton one.
  const Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(deformed.direction.data(), x.size());
  Eigen::VectorXd y = Eigen::VectorXd::Zero(x.size());
  for (int part = 0; part < ForceField::kParts; ++part)
    field.addStiffnessProduct(part, v.data(), y.data());
  const Eigen::VectorXd expected = gaussNewton * v;
  EXPECT_LT((y - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
    field.addDiagonalBlock(j, block);
    EXPECT_LT((block - gaussNewton.block<3, 3>(3 * j, 3 * j)).cwiseAbs().maxCoeff(), 1e-12 * scale);
  }
}

TEST(NodalVolumeForceField, PassesOnThePoolAreBitIdenticalToTheSerialOnes) {
  const TetMesh mesh = test::unstructuredBlock();
  const test::DeformedPositions deformed = test::stretchedAndJiggled(mesh.nodes_m, 7, 4e-4);
  test::expectPoolPassesBitIdentical(
      [&] { return NodalVolumeForceField(mesh.nodes_m, mesh.tets, 3e5); }, deformed.x,
      deformed.direction,
      [](const ForceReport& pooled, const ForceReport& serial) {
        return pooled.volume.minVolumeRatio == serial.volume.minVolumeRatio &&
               pooled.volume.maxVolumeRatio == serial.volume.maxVolumeRatio;
      });
}

TEST(NodalVolumeForceField, PushesAnInvertedTetBackOutAndCountsIt) {
  const TetMesh mesh = test::unstructuredBlock();
  const NodalVolumeForceField field(mesh.nodes_m, mesh.tets, 1e5);
  // An interior node of tet 0 pushed through its opposite face.
  Eigen::Matrix3Xd x = mesh.nodes_m;
  const Eigen::Vector4i tet = mesh.tets.col(0);
  const Eigen::Vector3d centroid = (x.col(tet[1]) + x.col(tet[2]) + x.col(tet[3])) / 3.0;
  const Eigen::Vector3d through = centroid - x.col(tet[0]);
  x.col(tet[0]) += 1.5 * through;
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  ForceReport report;
  field.addForces(x, f, ForcePass{}, report);
  EXPECT_GE(report.volume.invertedTetCount, 1);
  EXPECT_TRUE(f.allFinite());
  // Its force points back the way it came.
  EXPECT_LT(f.col(tet[0]).dot(through), 0.0);
}

// test::pressReaction with a volume per node and with VolumeForceField's cells, at kappa `low` and
// `high` times the tissue's shear modulus.
struct PressUnderTwoKappas {
  double nodes, nodesStiff, cells, cellsStiff;
};
PressUnderTwoKappas pressUnderTwoKappas(const TetMesh& mesh, double low, double high) {
  const double mu = test::liverEnergy().initialShearModulus();
  using test::BlockPress;
  return {
      test::pressReaction(mesh, {BlockPress::Strain::Tets, BlockPress::Volume::Nodes, low * mu}),
      test::pressReaction(mesh, {BlockPress::Strain::Tets, BlockPress::Volume::Nodes, high * mu}),
      test::pressReaction(mesh, {BlockPress::Strain::Tets, BlockPress::Volume::Cells, low * mu}),
      test::pressReaction(mesh, {BlockPress::Strain::Tets, BlockPress::Volume::Cells, high * mu})};
}

TEST(NodalVolumeForceField, LinearTetsStiffenWithKappaFarLessUnderItThanUnderAVolumePerTet) {
  // One volume constraint per linear tet (what VolumeForceField takes on a mesh with no lattice
  // cubes) outnumbers the DOFs: the press's force grows about as kappa once kappa is past the
  // shear modulus (locking). One per node leaves three DOFs for each: the force still grows
  // with kappa on this coarse unstructured block (a node with few tets, on the boundary, is
  // nearly a tet's constraint), but a hundred times kappa does not double it.
  const PressUnderTwoKappas press = pressUnderTwoKappas(test::unstructuredBlock(), 1e3, 1e5);
  ASSERT_GT(press.nodes, 0.0);
  EXPECT_LT(press.nodesStiff / press.nodes, 2.0);
  EXPECT_GT(press.cellsStiff / press.cells, 20.0);
  EXPECT_GT(press.cellsStiff / press.nodesStiff, 20.0);
}

TEST(NodalVolumeForceField, OnALatticeItSettlesAsKappaGrowsAsTheCubeCellsDo) {
  // On a Kuhn lattice, where VolumeForceField takes a cube per cell (Q1/P0), both settle: the
  // force moves by under 10 % from 10^4 to 10^6 times the shear modulus, and the two agree
  // within half.
  const PressUnderTwoKappas press =
      pressUnderTwoKappas(makeBlockMesh({0.02, 0.02, 0.01}, {8, 8, 4}), 1e4, 1e6);
  ASSERT_GT(press.cells, 0.0);
  EXPECT_LT(press.nodesStiff / press.nodes, 1.1);
  EXPECT_LT(press.cellsStiff / press.cells, 1.1);
  EXPECT_LT(std::abs(press.nodesStiff / press.cellsStiff - 1.0), 0.5);
}

}  // namespace
}  // namespace tissuesim
