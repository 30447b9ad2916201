#include "springs/VolumeForceField.h"

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "mesh/BlockMesher.h"

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

TEST(VolumeForceField, ForceIsMinusTheEnergyGradientAndHessianIsPsd) {
  const SpringMesh mesh = buildSpringMesh(makeBlockMesh({0.01, 0.01, 0.01}, {1, 1, 1}), 1000.0);
  const double kappa = 5e4;
  const VolumeForceField field(mesh, kappa);
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  x.row(0) *= 1.2;
  x(2, 7) -= 0.003;
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  Eigen::Matrix<double, 144, Eigen::Dynamic> blocks(144, mesh.tets.cols());
  field.addForces(x, f, &blocks);
  const double h = 1e-9;
  for (Eigen::Index d = 0; d < x.size(); ++d) {
    Eigen::Matrix3Xd up = x, down = x;
    up.data()[d] += h;
    down.data()[d] -= h;
    const double gradient =
        (volumeEnergy(mesh, up, kappa) - volumeEnergy(mesh, down, kappa)) / (2 * h);
    EXPECT_NEAR(f.data()[d], -gradient, 1e-6 * f.cwiseAbs().maxCoeff());
  }
  for (Eigen::Index t = 0; t < blocks.cols(); ++t) {
    const Eigen::Map<const Eigen::Matrix<double, 12, 12>> hessian(blocks.col(t).data());
    using Solver = Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>>;
    EXPECT_GE(Solver(hessian).eigenvalues().minCoeff(), -1e-9 * hessian.norm());
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
