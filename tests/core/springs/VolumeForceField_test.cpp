// SPDX-License-Identifier: Apache-2.0
#include "springs/VolumeForceField.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <random>
#include <utility>

#include "mesh/BlockMesher.h"
#include "mesh/TetMesh.h"
#include "numerics/NodeBlockMatrix.h"
#include "parallel/NodeRanges.h"
#include "springs/StiffnessCouplings.h"
#include "support/ForceFieldChecks.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

// The energy of a block mesh of cubes of edge h, summed cube by cube: each tet's cube found from
// its rest centroid, independently of how VolumeCells groups them.
double cubeVolumeEnergy(const SpringMesh& mesh, const Eigen::Matrix3Xd& x, double kappa, double h) {
  std::map<std::array<long, 3>, std::pair<double, double>> cubes;  // {V, V0}
  for (Eigen::Index t = 0; t < mesh.tets.cols(); ++t) {
    const std::array<long, 3> cube = test::cubeOfTet(mesh, t, h);
    cubes[cube].first += signedTetVolume(x, mesh.tets, t);
    cubes[cube].second += mesh.tetRestVolume_m3[t];
  }
  double energy = 0.0;
  for (const auto& [cube, volumes] : cubes) {
    const double j = volumes.first / volumes.second;
    energy += 0.5 * kappa * volumes.second * (j - 1) * (j - 1);
  }
  return energy;
}

double cellVolume(const SpringMesh& mesh, const VolumeCells& cells, const Eigen::Matrix3Xd& x,
                  Eigen::Index c) {
  double volume = 0.0;
  for (int k = cells.tetStart[static_cast<std::size_t>(c)];
       k < cells.tetStart[static_cast<std::size_t>(c) + 1]; ++k)
    volume += signedTetVolume(x, mesh.tets, cells.tets[static_cast<std::size_t>(k)]);
  return volume;
}

TEST(VolumeForceField, ForceIsMinusTheEnergyGradientAndBlocksHoldTheVolumeGradient) {
  const double h = 0.01;
  const SpringMesh mesh = buildSpringMesh(makeBlockMesh({2 * h, h, h}, {2, 1, 1}), 1000.0);
  const double kappa = 5e4;
  const VolumeForceField field(mesh, kappa);
  ASSERT_EQ(field.cells().cellCount(), 2);
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  x.row(0) *= 1.2;
  x(2, 7) -= 0.003;
  x(1, 3) += 0.002;
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  VolumeBlocks blocks(kVolumeBlockRows, field.cells().cellCount());
  const VolumeFieldReport report = field.addForces(x, f, &blocks);
  const double energy = cubeVolumeEnergy(mesh, x, kappa, h);
  ASSERT_GT(energy, 0.0);
  EXPECT_NEAR(field.energy(x), energy, 1e-12 * energy);
  EXPECT_GT(report.maxVolumeRatio, 1.1);  // stretched 20 % along x
  const double step = 1e-9;
  for (Eigen::Index d = 0; d < x.size(); ++d) {
    Eigen::Matrix3Xd up = x, down = x;
    up.data()[d] += step;
    down.data()[d] -= step;
    const double gradient =
        (cubeVolumeEnergy(mesh, up, kappa, h) - cubeVolumeEnergy(mesh, down, kappa, h)) /
        (2 * step);
    EXPECT_NEAR(f.data()[d], -gradient, 1e-6 * f.cwiseAbs().maxCoeff());
  }
  // Each block: g = dV/dx on the cell's nodes by central differences (V is linear in each
  // coordinate: exact to rounding), zero in unused slots, and k = kappa / V0.
  const VolumeCells& cells = field.cells();
  for (Eigen::Index c = 0; c < cells.cellCount(); ++c) {
    const double norm = blocks.col(c).head<kVolumeBlockRows - 1>().norm();
    for (int i = 0; i < VolumeCells::kMaxNodes; ++i) {
      for (int axis = 0; axis < 3; ++axis) {
        double gradient = 0.0;
        if (i < cells.nodeCount[static_cast<std::size_t>(c)]) {
          Eigen::Matrix3Xd up = x, down = x;
          up(axis, cells.nodes(i, c)) += 1e-6;
          down(axis, cells.nodes(i, c)) -= 1e-6;
          gradient = (cellVolume(mesh, cells, up, c) - cellVolume(mesh, cells, down, c)) / 2e-6;
        }
        EXPECT_NEAR(blocks(3 * i + axis, c), gradient, 1e-9 * norm);
      }
    }
    EXPECT_DOUBLE_EQ(blocks(kVolumeBlockRows - 1, c), kappa / (h * h * h));
  }
}

TEST(VolumeForceField, TheAssembledExactHessianIsMinusTheForcesDerivative) {
  // Asked for the exact Hessian, the assembled matrix is -df/dx (central differences of the
  // forces) at a state whose cells are far from their rest volume; asked for the PSD part, it
  // is the Gauss-Newton sum_c k g g^T alone, which misses p d^2V/dx^2 there.
  const double h = 0.01;
  const SpringMesh mesh = buildSpringMesh(makeBlockMesh({2 * h, h, h}, {2, 1, 1}), 1000.0);
  const double kappa = 5e4;
  const VolumeForceField field(mesh, kappa);
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  x.row(0) *= 1.2;
  x(2, 7) -= 0.003;
  x(1, 3) += 0.002;
  const Eigen::Matrix2Xi couplings = stiffnessCouplings(mesh, &field.cells());
  const Eigen::MatrixXd exact = test::assembledStiffness(field, x, couplings, false);
  const Eigen::MatrixXd gaussNewton = test::assembledStiffness(field, x, couplings, true);
  const Eigen::MatrixXd differences = test::forceDerivative(field, x, 1e-7);
  const double scale = differences.cwiseAbs().maxCoeff();
  EXPECT_LT((exact - differences).cwiseAbs().maxCoeff(), 1e-6 * scale);
  EXPECT_LT((exact - exact.transpose()).cwiseAbs().maxCoeff(), 1e-12 * scale);
  EXPECT_GT((gaussNewton - differences).cwiseAbs().maxCoeff(), 1e-2 * scale);
}

TEST(VolumeForceField, PassesOnThePoolAreBitIdenticalToTheSerialOnes) {
  // Above the node-wise passes' pool threshold (parallel/NodeRanges.h), so both passes split.
  const SpringMesh mesh = buildSpringMesh(makeBlockMesh({0.2, 0.2, 0.2}, {20, 20, 20}), 1000.0);
  ASSERT_GE(mesh.nodeCount(), kParallelNodePassMinimum);
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += 1e-4 * std::sin(1.7 * i);
  const VolumeForceField serial(mesh, 3e5);
  Eigen::Matrix3Xd expected = Eigen::Matrix3Xd::Zero(3, x.cols());
  VolumeBlocks expectedBlocks(kVolumeBlockRows, serial.cells().cellCount());
  const VolumeFieldReport expectedReport = serial.addForces(x, expected, &expectedBlocks);
  Eigen::VectorXd expectedBound = Eigen::VectorXd::Zero(x.cols());
  serial.addNodeStiffnessBound(expectedBound);
  ASSERT_GT(expected.cwiseAbs().maxCoeff(), 0.0);
  for (const int threads : {1, 2, 3}) {
    ForkJoinPool pool(threads);
    VolumeForceField pooled(mesh, 3e5);
    pooled.setThreadPool(&pool);
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
    VolumeBlocks blocks(kVolumeBlockRows, pooled.cells().cellCount());
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

TEST(VolumeForceField, ATetSqueezedBelowHalfItsVolumeIsPushedBackOnItsOwn) {
  // One cube of six tets; one corner pushed 70 % of the way to its tet's opposite face, which
  // squeezes that tet to 0.3 of its volume (and changes its neighbours'). Beyond the cube's term,
  // each tet below J_g = 1/2 adds 1/2 kappa V0 (J - J_g)^2: its
  // force, its Gauss-Newton stiffness in the products, the diagonal blocks and the assembled
  // matrix, and its exact Hessian there.
  const double h = 0.01;
  const SpringMesh mesh = buildSpringMesh(makeBlockMesh({h, h, h}, {1, 1, 1}), 1000.0);
  const double kappa = 5e4;
  VolumeForceField field(mesh, kappa);
  const Eigen::Vector4i squeezed = mesh.tets.col(0);
  Eigen::Matrix3Xd x = mesh.restPositions_m;
  const Eigen::Vector3d face = (x.col(squeezed[1]) + x.col(squeezed[2]) + x.col(squeezed[3])) / 3.0;
  x.col(squeezed[0]) += 0.7 * (face - x.col(squeezed[0]));
  ASSERT_NEAR(signedTetVolume(x, mesh.tets, 0) / mesh.tetRestVolume_m3[0], 0.3, 1e-12);
  const auto guardEnergy = [&](const Eigen::Matrix3Xd& at) {
    double energy = 0.0;
    for (Eigen::Index t = 0; t < mesh.tets.cols(); ++t) {
      const double below = signedTetVolume(at, mesh.tets, t) / mesh.tetRestVolume_m3[t] - 0.5;
      if (below < 0.0) energy += 0.5 * kappa * mesh.tetRestVolume_m3[t] * below * below;
    }
    return energy;
  };
  const double guard = guardEnergy(x);
  ASSERT_GT(guard, 0.0);
  EXPECT_NEAR(field.energy(x), cubeVolumeEnergy(mesh, x, kappa, h) + guard,
              1e-12 * field.energy(x));
  // Forces: minus the gradient of the cube's and the guard's energies.
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
  ForcePass pass;
  pass.stiffness = StiffnessSlot::Current;
  ForceReport report;
  field.prepareProducts({0, 2, 4, 6, x.cols()});
  field.addForces(x, f, pass, report);
  const double step = 1e-9;
  for (Eigen::Index d = 0; d < x.size(); ++d) {
    Eigen::Matrix3Xd up = x, down = x;
    up.data()[d] += step;
    down.data()[d] -= step;
    const double gradient = (cubeVolumeEnergy(mesh, up, kappa, h) + guardEnergy(up) -
                             cubeVolumeEnergy(mesh, down, kappa, h) - guardEnergy(down)) /
                            (2 * step);
    EXPECT_NEAR(f.data()[d], -gradient, 1e-6 * f.cwiseAbs().maxCoeff());
  }
  // The squeezed tet's apex is pushed back away from its face.
  EXPECT_GT(f.col(squeezed[0]).dot(x.col(squeezed[0]) - face), 0.0);
  // Stiffness: the products and the diagonal blocks are the assembled Gauss-Newton matrix's.
  NodeBlockMatrix matrix(mesh.nodeCount(), stiffnessCouplings(mesh, &field.cells()));
  matrix.setZero();
  field.addStiffness(matrix);
  const Eigen::MatrixXd dense(matrix.matrix());
  Eigen::VectorXd direction(x.size());
  for (Eigen::Index i = 0; i < direction.size(); ++i) direction[i] = std::sin(2.3 * i + 0.4);
  Eigen::VectorXd product = Eigen::VectorXd::Zero(x.size());
  for (int part = 0; part < ForceField::kParts; ++part)
    field.addStiffnessProduct(part, direction.data(), product.data());
  const Eigen::VectorXd expected = dense * direction;
  EXPECT_LT((product - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff());
  for (Eigen::Index j = 0; j < mesh.nodeCount(); ++j) {
    Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
    field.addDiagonalBlock(j, block);
    EXPECT_LT((block - dense.block(3 * j, 3 * j, 3, 3)).cwiseAbs().maxCoeff(),
              1e-10 * dense.cwiseAbs().maxCoeff());
  }
  // The exact Hessian, asked for, is -df/dx there.
  pass.isProjected = false;
  field.addForces(x, f, pass, report);
  matrix.setZero();
  field.addStiffness(matrix);
  const Eigen::MatrixXd exact(matrix.matrix());
  for (Eigen::Index d = 0; d < x.size(); ++d) {
    Eigen::Matrix3Xd up = x, down = x;
    up.data()[d] += 1e-8;
    down.data()[d] -= 1e-8;
    Eigen::Matrix3Xd fUp = Eigen::Matrix3Xd::Zero(3, x.cols());
    Eigen::Matrix3Xd fDown = Eigen::Matrix3Xd::Zero(3, x.cols());
    field.addForces(up, fUp, nullptr);
    field.addForces(down, fDown, nullptr);
    const Eigen::Matrix3Xd change = (fDown - fUp) / 2e-8;
    const Eigen::VectorXd column = Eigen::Map<const Eigen::VectorXd>(change.data(), x.size());
    EXPECT_LT((exact.col(d) - column).cwiseAbs().maxCoeff(), 1e-6 * exact.cwiseAbs().maxCoeff())
        << d;
  }
}

TEST(VolumeForceField, TheProductsTwoLoopsApplyTheCellsRankOneTerms) {
  // A lattice (cubes of 8 nodes) and the same lattice jiggled (a cell per tet, 4 nodes), moved
  // off rest; x random. Both kernels (the AVX one where the CPU has it) against sum k g (g . x)
  // summed here cell by cell.
  for (const bool isJiggled : {false, true}) {
    TetMesh lattice = makeBlockMesh({0.04, 0.03, 0.02}, {4, 3, 2});
    std::mt19937 random(11);
    std::uniform_real_distribution<double> jiggle(-5e-4, 5e-4);
    if (isJiggled) {
      for (Eigen::Index i = 0; i < lattice.nodes_m.size(); ++i)
        lattice.nodes_m.data()[i] += jiggle(random);
    }
    const SpringMesh mesh = buildSpringMesh(lattice, 1000.0);
    const VolumeForceField field(mesh, 1e5);
    Eigen::Matrix3Xd x = mesh.restPositions_m;
    for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += 2.0 * jiggle(random);
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, x.cols());
    VolumeBlocks blocks(kVolumeBlockRows, field.cells().cellCount());
    field.addForces(x, f, &blocks);
    const Eigen::Index n = mesh.nodeCount();
    const VolumeStiffnessProduct::PartBounds bounds{0, n / 5, n / 2, 3 * n / 4, n};
    Eigen::VectorXd v(3 * n);
    for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = jiggle(random) * 1e3;
    Eigen::VectorXd expected = Eigen::VectorXd::Zero(3 * n);
    const VolumeCells& cells = field.cells();
    for (Eigen::Index c = 0; c < cells.cellCount(); ++c) {
      const int count = cells.nodeCount[static_cast<std::size_t>(c)];
      double gv = 0.0;
      for (int i = 0; i < count; ++i)
        gv += blocks.col(c).segment<3>(3 * i).dot(v.segment<3>(3 * cells.nodes(i, c)));
      for (int i = 0; i < count; ++i) {
        expected.segment<3>(3 * cells.nodes(i, c)) +=
            blocks(kVolumeBlockRows - 1, c) * gv * blocks.col(c).segment<3>(3 * i);
      }
    }
    ASSERT_GT(expected.norm(), 0.0);
    for (const auto kernel :
         {VolumeStiffnessProduct::Kernel::Fastest, VolumeStiffnessProduct::Kernel::Portable}) {
      const VolumeStiffnessProduct product(cells, bounds, kernel);
      Eigen::VectorXd y = Eigen::VectorXd::Zero(3 * n);
      for (int part = 0; part < VolumeStiffnessProduct::kParts; ++part)
        product.addPart(part, blocks, v.data(), y.data());
      EXPECT_LT((y - expected).norm(), 1e-13 * expected.norm())
          << (isJiggled ? "tets, " : "cubes, ")
          << (kernel == VolumeStiffnessProduct::Kernel::Fastest ? "fastest" : "portable");
    }
  }
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
