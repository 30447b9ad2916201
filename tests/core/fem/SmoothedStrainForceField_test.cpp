// SPDX-License-Identifier: Apache-2.0
// The isochoric energy in smoothing cells, per face (FS-FEM) and per node (NS-FEM): its energy is
// each cell's share at the mean of its tets' F, its forces the energy's negative gradient, its
// exact stiffness the forces' derivative in every form (products, diagonal blocks, assembly), its
// projected stiffness PSD; under a homogeneous deformation it is the tets' FEM exactly;
// elsewhere it is softer than the tets' FEM, per node softer than per face; per tet and per node
// bracket a press's force as the mesh is refined, per face between them; the passes give the same
// bits on any thread count.

#include "fem/SmoothedStrainForceField.h"

#include <array>
#include <map>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "fem/StrainCells.h"
#include "fem/TetIsochoricForceField.h"
#include "mesh/BlockMesher.h"
#include "mesh/TetMesh.h"
#include "mesh/TetMeshFile.h"
#include "parallel/ForkJoinPool.h"
#include "support/BlockPress.h"
#include "support/ForceFieldChecks.h"
#include "support/TestMeshes.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

enum class Cells { Faces, Nodes };

StrainCells cellsOf(const TetMesh& mesh, Cells kind) {
  return kind == Cells::Faces ? faceStrainCells(mesh.nodes_m, mesh.tets)
                              : nodeStrainCells(mesh.nodes_m, mesh.tets);
}

SmoothedStrainForceField fieldOn(const TetMesh& mesh, Cells kind) {
  return SmoothedStrainForceField(cellsOf(mesh, kind), mesh.nodeCount(), test::liverEnergy());
}

Eigen::Matrix3d tetDeformation(const Eigen::Matrix3Xd& rest, const Eigen::Matrix3Xd& x,
                               const Eigen::Vector4i& tet) {
  Eigen::Matrix3d dm, ds;
  for (int c = 1; c < 4; ++c) {
    dm.col(c - 1) = rest.col(tet[c]) - rest.col(tet[0]);
    ds.col(c - 1) = x.col(tet[c]) - x.col(tet[0]);
  }
  return ds * dm.inverse();
}

// The energy from its definition: each cell (a face's tets, or a node's) a quarter of each of its
// tets, at their volume-weighted mean F.
double smoothedEnergy(const TetMesh& mesh, const Eigen::Matrix3Xd& x, Cells kind) {
  std::map<std::array<int, 3>, std::pair<Eigen::Matrix3d, double>> cells;
  for (Eigen::Index t = 0; t < mesh.tets.cols(); ++t) {
    const Eigen::Matrix3d f = tetDeformation(mesh.nodes_m, x, mesh.tets.col(t));
    const double share = signedTetVolume(mesh.nodes_m, mesh.tets, t) / 4;
    for (int c = 0; c < 4; ++c) {
      std::array<int, 3> key{mesh.tets(c, t), -1, -1};
      if (kind == Cells::Faces) {
        for (int k = 0, n = 0; k < 4; ++k) {
          if (k != c) key[static_cast<std::size_t>(n++)] = mesh.tets(k, t);
        }
        std::sort(key.begin(), key.end());
      }
      auto& [sum, volume] = cells.try_emplace(key, Eigen::Matrix3d::Zero(), 0.0).first->second;
      sum += share * f;
      volume += share;
    }
  }
  double energy = 0.0;
  for (const auto& [key, cell] : cells) {
    const Eigen::Matrix3d f = cell.first / cell.second;
    const double i1bar = std::pow(f.determinant(), -2.0 / 3.0) * f.squaredNorm();
    energy += cell.second * test::liverEnergy().atInvariantShift(std::max(i1bar - 3.0, 0.0)).energy;
  }
  return energy;
}

Eigen::Matrix3Xd forcesOf(const ForceField& field, const Eigen::Matrix3Xd& x,
                          ForceReport* report = nullptr) {
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  ForceReport local;
  field.addForces(x, f, ForcePass{}, report != nullptr ? *report : local);
  return f;
}

class SmoothedStrain : public ::testing::TestWithParam<Cells> {};

TEST_P(SmoothedStrain, ItsEnergyIsTheCellsMeanStrainsAndItsForcesTheNegativeGradient) {
  const TetMesh mesh = test::unstructuredBlock();
  ASSERT_GT(mesh.tets.cols(), 100);
  const SmoothedStrainForceField field = fieldOn(mesh, GetParam());
  // Jiggled less than the other tests: a boundary node of one small tet would pass locking.
  const test::DeformedPositions deformed = test::stretchedAndJiggled(mesh.nodes_m, 3, 1e-4);
  const Eigen::Matrix3Xd& x = deformed.x;
  const double energy = smoothedEnergy(mesh, x, GetParam());
  ASSERT_GT(energy, 0.0);
  EXPECT_NEAR(field.energy(x), energy, 1e-10 * energy);
  ForceReport report;
  const Eigen::Matrix3Xd f = forcesOf(field, x, &report);
  EXPECT_EQ(report.tets.invertedCount, 0);
  EXPECT_EQ(report.tets.beyondRangeCount, 0);
  const double step = 1e-9;
  const double scale = f.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  for (Eigen::Index d = 0; d < x.size(); d += 5) {
    Eigen::Matrix3Xd up = x, down = x;
    up.data()[d] += step;
    down.data()[d] -= step;
    const double gradient =
        (smoothedEnergy(mesh, up, GetParam()) - smoothedEnergy(mesh, down, GetParam())) /
        (2 * step);
    EXPECT_NEAR(f.data()[d], -gradient, 1e-6 * scale) << "DOF " << d;
  }
}

TEST_P(SmoothedStrain, TheStiffnessIsTheForcesDerivativeInEveryForm) {
  const TetMesh mesh = test::unstructuredBlock();
  SmoothedStrainForceField field = fieldOn(mesh, GetParam());
  field.prepareProducts({0, 7, 20, 31, mesh.nodes_m.cols()});  // uneven parts on purpose
  test::DeformedPositions deformed = test::stretchedAndJiggled(mesh.nodes_m, 5, 4e-4);
  const Eigen::Matrix3Xd& x = deformed.x;
  const Eigen::Matrix2Xi couplings = field.couplings();
  const Eigen::MatrixXd differences = test::forceDerivative(field, x, 1e-8);
  const double scale = differences.cwiseAbs().maxCoeff();
  // The exact Hessian (assembled last, so the products and blocks below read it).
  const Eigen::MatrixXd exact = test::assembledStiffness(field, x, couplings, false);
  EXPECT_LT((exact - differences).cwiseAbs().maxCoeff(), 1e-6 * scale);
  EXPECT_LT((exact - exact.transpose()).cwiseAbs().maxCoeff(), 1e-12 * scale);
  const Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(deformed.direction.data(), x.size());
  Eigen::VectorXd y = Eigen::VectorXd::Zero(x.size());
  for (int part = 0; part < ForceField::kParts; ++part)
    field.addStiffnessProduct(part, v.data(), y.data());
  const Eigen::VectorXd expected = exact * v;
  EXPECT_LT((y - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff());
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
    field.addDiagonalBlock(j, block);
    EXPECT_LT((block - exact.block<3, 3>(3 * j, 3 * j)).cwiseAbs().maxCoeff(), 1e-12 * scale);
  }

  // The explicit integrator's bound on each node's row of K holds the row.
  Eigen::VectorXd bound = Eigen::VectorXd::Zero(x.cols());
  ForcePass boundPass;
  boundPass.nodeStiffness = &bound;
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  ForceReport report;
  field.addForces(x, f, boundPass, report);
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    const double row = exact.middleRows<3>(3 * j).norm();
    EXPECT_GE(bound[j], (1 - 1e-12) * row) << "node " << j;
  }
}

TEST_P(SmoothedStrain, TheProjectedStiffnessIsPositiveSemiDefiniteWhereTheExactIsNot) {
  const TetMesh mesh = test::unstructuredBlock();
  const SmoothedStrainForceField field = fieldOn(mesh, GetParam());
  // Strongly sheared and compressed: the exact Hessian of I1bar is indefinite there.
  Eigen::Matrix3Xd x = mesh.nodes_m;
  x.row(0) += 0.8 * mesh.nodes_m.row(2);
  x.row(2) *= 0.6;
  const Eigen::Matrix2Xi couplings = field.couplings();
  const Eigen::VectorXd projected = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(
                                        test::assembledStiffness(field, x, couplings, true))
                                        .eigenvalues();
  EXPECT_GT(projected.minCoeff(), -1e-9 * projected.maxCoeff());
  const Eigen::VectorXd exact = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(
                                    test::assembledStiffness(field, x, couplings, false))
                                    .eigenvalues();
  EXPECT_LT(exact.minCoeff(), -1e-6 * projected.maxCoeff());
}

TEST_P(SmoothedStrain, UnderAHomogeneousDeformationItIsTheTetsFem) {
  // Every tet's F is then the same, so is every cell's, and each node's force is the tets'.
  const TetMesh mesh = test::unstructuredBlock();
  const SmoothedStrainForceField cells = fieldOn(mesh, GetParam());
  const TetIsochoricForceField tets(mesh.nodes_m, mesh.tets, test::liverEnergy());
  Eigen::Matrix3d f;
  f << 1.2, 0.05, -0.03, 0.02, 0.93, 0.04, -0.01, 0.03, 0.91;
  const Eigen::Matrix3Xd x = f * mesh.nodes_m;
  const Eigen::Matrix3Xd expected = forcesOf(tets, x);
  ASSERT_GT(expected.norm(), 0.0);
  EXPECT_LT((forcesOf(cells, x) - expected).norm(), 1e-12 * expected.norm());
  EXPECT_NEAR(cells.energy(x), tets.energy(x), 1e-12 * tets.energy(x));
}

TEST_P(SmoothedStrain, PastLockingAndInvertedCellsAreCountedAndStayFinite) {
  const TetMesh mesh = makeBlockMesh({0.01, 0.01, 0.01}, {1, 1, 1});
  const SmoothedStrainForceField field = fieldOn(mesh, GetParam());
  const Eigen::Index cellCount = field.cells().cellCount();
  Eigen::Matrix3Xd x = mesh.nodes_m;
  x.row(0) *= 2.5;  // far past lambda 1.5, where the chains lock
  x.bottomRows(2) /= std::sqrt(2.5);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  ForceReport report;
  ForcePass pass;
  pass.stiffness = StiffnessSlot::Current;
  field.addForces(x, f, pass, report);
  EXPECT_EQ(report.tets.beyondRangeCount, cellCount);
  EXPECT_TRUE(f.allFinite());
  EXPECT_TRUE(std::isfinite(field.energy(x)));
  EXPECT_GT(f.norm(), 0.0);

  x = mesh.nodes_m;
  x.row(2) *= -1.0;  // every tet mirrored
  f.setZero();
  report = {};
  field.addForces(x, f, pass, report);
  EXPECT_EQ(report.tets.invertedCount, cellCount);
  EXPECT_TRUE(f.allFinite());
}

TEST_P(SmoothedStrain, PassesOnThePoolAreBitIdenticalToTheSerialOnes) {
  const TetMesh mesh = test::unstructuredBlock();
  const test::DeformedPositions deformed = test::stretchedAndJiggled(mesh.nodes_m, 7, 4e-4);
  test::expectPoolPassesBitIdentical(
      [&] { return fieldOn(mesh, GetParam()); }, deformed.x, deformed.direction,
      [](const ForceReport& pooled, const ForceReport& serial) {
        return pooled.tets.beyondRangeCount == serial.tets.beyondRangeCount &&
               pooled.tets.invertedCount == serial.tets.invertedCount;
      });
}

INSTANTIATE_TEST_SUITE_P(FacesAndNodes, SmoothedStrain,
                         ::testing::Values(Cells::Faces, Cells::Nodes),
                         [](const ::testing::TestParamInfo<Cells>& param) {
                           return param.param == Cells::Faces ? "faces" : "nodes";
                         });

TEST(SmoothedStrainForceField, PerFaceItIsSofterThanTheTetsFemAndPerNodeSofterStill) {
  // Away from a homogeneous state each cell's energy is taken at its tets' mean strain, which for
  // the tissue's convex energy near rest is below the mean of their energies; a node's cell
  // averages over more tets than a face's.
  const TetMesh mesh = test::unstructuredBlock();
  const TetIsochoricForceField tets(mesh.nodes_m, mesh.tets, test::liverEnergy());
  const SmoothedStrainForceField faces = fieldOn(mesh, Cells::Faces);
  const SmoothedStrainForceField nodes = fieldOn(mesh, Cells::Nodes);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int trial = 0; trial < 4; ++trial) {
    Eigen::Matrix3Xd x = mesh.nodes_m;
    for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += 2e-4 * uniform(random);
    const double tetEnergy = tets.energy(x);
    const double faceEnergy = faces.energy(x);
    ASSERT_GT(tetEnergy, 0.0);
    EXPECT_LT(faceEnergy, 0.95 * tetEnergy) << "trial " << trial;
    EXPECT_LT(nodes.energy(x), 0.95 * faceEnergy) << "trial " << trial;
  }
}

TEST(SmoothedStrainForceField, PerTetAndPerNodeBracketAPressAsTheMeshIsRefinedPerFaceBetween) {
  // The press of a block on its held bottom with a volume per node at a thousand times the
  // shear modulus: per tet the force comes down and per node it goes up as the lattice is
  // refined, per tet above per node on each, per face between the two.
  using test::BlockPress;
  const double kappa = 1e3 * test::liverEnergy().initialShearModulus();
  const TetMesh coarse = makeBlockMesh({0.02, 0.02, 0.01}, {4, 4, 2});
  const TetMesh fine = makeBlockMesh({0.02, 0.02, 0.01}, {8, 8, 4});
  const auto press = [&](const TetMesh& mesh, BlockPress::Strain strain) {
    return test::pressReaction(mesh, {strain, BlockPress::Volume::Nodes, kappa});
  };
  const double tetsCoarse = press(coarse, BlockPress::Strain::Tets);
  const double tetsFine = press(fine, BlockPress::Strain::Tets);
  const double facesFine = press(fine, BlockPress::Strain::Faces);
  const double nodesCoarse = press(coarse, BlockPress::Strain::Nodes);
  const double nodesFine = press(fine, BlockPress::Strain::Nodes);
  ASSERT_GT(nodesCoarse, 0.0);
  EXPECT_GT(tetsCoarse, tetsFine);
  EXPECT_GT(tetsFine, nodesFine);
  EXPECT_GT(nodesFine, nodesCoarse);
  EXPECT_LT(facesFine, tetsFine);
  EXPECT_GT(facesFine, nodesFine);
}

}  // namespace
}  // namespace tissuesim
