#include "springs/VolumeForceField.h"

#include <gtest/gtest.h>

#include <cmath>

#include "mesh/BlockMesher.h"
#include "parallel/NodeRanges.h"

namespace tissuesim {
namespace {

double volumeEnergy(const SpringMesh& mesh, const Eigen::Matrix3Xd& x, double kappa) {
  double energy = 0.0;
  for (Eigen::Index t = 0; t < mesh.tets.cols(); ++t) {
    const double j = signedTetVolume(x, mesh.tets, t) / mesh.tetRestVolume_m3[t];
    energy += 0.5 * kappa * mesh.tetRestVolume_m3[t] * (j - 1) * (j - 1);
  }
  return energy;
}

TEST(VolumeForceField, ForceIsMinusTheEnergyGradientAndBlocksHoldTheVolumeGradient) {
  const SpringMesh mesh = buildSpringMesh(makeBlockMesh({0.01, 0.01, 0.01}, {1, 1, 1}), 1000.0);
  const double kappa = 5e4;
  const VolumeForceField field(mesh, kappa);
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  x.row(0) *= 1.2;
  x(2, 7) -= 0.003;
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  VolumeBlocks blocks(13, mesh.tets.cols());
  const VolumeFieldReport report = field.addForces(x, f, &blocks);
  EXPECT_NEAR(field.energy(x), volumeEnergy(mesh, x, kappa), 1e-12 * volumeEnergy(mesh, x, kappa));
  EXPECT_GT(report.maxVolumeRatio, 1.1);  // stretched 20 % along x
  const double h = 1e-9;
  for (Eigen::Index d = 0; d < x.size(); ++d) {
    Eigen::Matrix3Xd up = x, down = x;
    up.data()[d] += h;
    down.data()[d] -= h;
    const double gradient =
        (volumeEnergy(mesh, up, kappa) - volumeEnergy(mesh, down, kappa)) / (2 * h);
    EXPECT_NEAR(f.data()[d], -gradient, 1e-6 * f.cwiseAbs().maxCoeff());
  }
  // Each block: g = dV/dx by central differences (V is linear in each coordinate: exact to
  // rounding), and c = kappa / V0.
  for (Eigen::Index t = 0; t < blocks.cols(); ++t) {
    for (int i = 0; i < 4; ++i) {
      for (int axis = 0; axis < 3; ++axis) {
        Eigen::Matrix3Xd up = x, down = x;
        up(axis, mesh.tets(i, t)) += 1e-6;
        down(axis, mesh.tets(i, t)) -= 1e-6;
        const double gradient =
            (signedTetVolume(up, mesh.tets, t) - signedTetVolume(down, mesh.tets, t)) / 2e-6;
        EXPECT_NEAR(blocks(3 * i + axis, t), gradient, 1e-9 * blocks.col(t).head<12>().norm());
      }
    }
    EXPECT_DOUBLE_EQ(blocks(12, t), kappa / mesh.tetRestVolume_m3[t]);
  }
}

TEST(VolumeForceField, PassesOnThePoolAreBitIdenticalToTheSerialOnes) {
  // Above the node-wise passes' pool threshold (parallel/NodeRanges.h), so both passes split.
  const SpringMesh mesh = buildSpringMesh(makeBlockMesh({0.2, 0.2, 0.2}, {20, 20, 20}), 1000.0);
  ASSERT_GE(mesh.nodeCount(), kParallelNodePassMinimum);
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += 1e-4 * std::sin(1.7 * i);
  const VolumeForceField serial(mesh, 3e5);
  Eigen::Matrix3Xd expected = Eigen::Matrix3Xd::Zero(3, x.cols());
  VolumeBlocks expectedBlocks(13, mesh.tets.cols());
  const VolumeFieldReport expectedReport = serial.addForces(x, expected, &expectedBlocks);
  Eigen::VectorXd expectedBound = Eigen::VectorXd::Zero(x.cols());
  serial.addNodeStiffnessBound(expectedBound);
  ASSERT_GT(expected.cwiseAbs().maxCoeff(), 0.0);
  for (const int threads : {1, 2, 3}) {
    ForkJoinPool pool(threads);
    VolumeForceField pooled(mesh, 3e5);
    pooled.setThreadPool(&pool);
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
    VolumeBlocks blocks(13, mesh.tets.cols());
    const VolumeFieldReport report = pooled.addForces(x, f, &blocks);
    EXPECT_EQ(f, expected) << threads << " threads";
    EXPECT_EQ(blocks, expectedBlocks) << threads << " threads";
    EXPECT_EQ(report.minVolumeRatio, expectedReport.minVolumeRatio);
    EXPECT_EQ(report.maxVolumeRatio, expectedReport.maxVolumeRatio);
    Eigen::VectorXd bound = Eigen::VectorXd::Zero(x.cols());
    pooled.addNodeStiffnessBound(bound);
    EXPECT_EQ(bound, expectedBound) << threads << " threads";
  }
}

TEST(VolumeForceField, PushesAnInvertedTetBackOut) {
  TetMesh tet;
  tet.nodes_m.resize(3, 4);
  tet.nodes_m << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  tet.tets.resize(4, 1);
  tet.tets << 0, 1, 2, 3;
  const SpringMesh mesh = buildSpringMesh(tet, 1000.0);
  const VolumeForceField field(mesh, 1e3);
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  x(2, 3) = -0.5;  // apex pushed through the base: inverted
  const VolumeFieldReport report = VolumeForceField::inspect(mesh, x);
  EXPECT_EQ(report.invertedTetCount, 1);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, 4);
  field.addForces(x, f, nullptr);
  EXPECT_GT(f(2, 3), 0.0);  // the apex is pushed back up
}

TEST(VolumeForceField, InspectionOnThePoolFindsWhatTheSerialOneDoes) {
  const SpringMesh mesh = buildSpringMesh(makeBlockMesh({0.04, 0.04, 0.04}, {4, 4, 4}), 1000.0);
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  // Every eighth node pushed through its neighbours: inverted tets all along the tet list, so
  // in each of the pool's ranges.
  for (Eigen::Index node = 0; node < mesh.nodeCount(); node += 8) {
    x.col(node) += Eigen::Vector3d(0.012, 0.011, 0.013);
  }
  const VolumeFieldReport serial = VolumeForceField::inspect(mesh, x);
  ASSERT_GE(serial.invertedTetCount, 20);
  for (const int threads : {1, 2, 3}) {
    ForkJoinPool pool(threads);
    const VolumeFieldReport pooled = VolumeForceField::inspect(mesh, x, &pool);
    EXPECT_EQ(pooled.invertedTetCount, serial.invertedTetCount) << threads << " threads";
    EXPECT_EQ(pooled.minVolumeRatio, serial.minVolumeRatio) << threads << " threads";
  }
}

}  // namespace
}  // namespace tissuesim
