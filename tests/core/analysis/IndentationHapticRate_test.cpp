// SPDX-License-Identifier: Apache-2.0
// The indentation test at the haptic rate: the graded grid's lines and the whole block's mesh are
// what they say, and the block pressed at the haptic rate on the reference's own grid, mirrored,
// gives the reference's force.

#include "analysis/IndentationHapticRate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "fem/FemModel.h"
#include "mesh/TetMesh.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

TEST(GradedGridLine, ItsCellsGrowFromTheFinestToTheCoarsestAndEndAtTheLength) {
  const std::vector<double> line = gradedGridLine(0.03, 0.002, 1.5, 0.006);
  ASSERT_GE(line.size(), 5u);
  EXPECT_EQ(line.front(), 0.0);
  EXPECT_DOUBLE_EQ(line.back(), 0.03);
  EXPECT_DOUBLE_EQ(line[1], 0.002);
  EXPECT_NEAR(line[2] - line[1], 0.003, 1e-15);
  for (std::size_t i = 1; i + 1 < line.size(); ++i) {
    const double cell = line[i] - line[i - 1];
    const double next = line[i + 1] - line[i];
    EXPECT_GT(next, 0.0) << i;
    // Every cell but the last: the one before times the growth, at most the coarsest.
    if (i + 2 < line.size()) {
      EXPECT_NEAR(next, std::min(1.5 * cell, 0.006), 1e-15) << i;
    }
  }
  // The last cell takes what is left: no sliver under half a cell.
  EXPECT_GT(line.back() - line[line.size() - 2], 0.5 * 0.006 - 1e-15);
  EXPECT_THROW(gradedGridLine(0.03, 0.0, 1.5, 0.006), std::invalid_argument);
  EXPECT_THROW(gradedGridLine(0.03, 0.002, 0.9, 0.006), std::invalid_argument);
  EXPECT_THROW(gradedGridLine(0.03, 0.002, 1.5, 0.001), std::invalid_argument);
  EXPECT_THROW(gradedGridLine(-0.03, 0.002, 1.5, 0.006), std::invalid_argument);
}

TEST(IndentationBlockMesh, ItFillsTheBlockGradedSymmetricallyTowardsTheTopCentre) {
  IndentationSetup setup;  // 60 x 60 x 30 mm
  const TetMesh mesh = indentationBlockMesh(setup, 0.0025, 2.0, 0.015);
  const Eigen::Vector3d low = mesh.nodes_m.rowwise().minCoeff();
  const Eigen::Vector3d high = mesh.nodes_m.rowwise().maxCoeff();
  EXPECT_LT(low.norm(), 1e-15);
  EXPECT_LT((high - setup.size_m).norm(), 1e-15);
  double volume_m3 = 0.0;
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    const double v = signedTetVolume(mesh.nodes_m, mesh.tets, t);
    EXPECT_GT(v, 0.0) << t;
    volume_m3 += v;
  }
  EXPECT_NEAR(volume_m3, setup.size_m.prod(), 1e-12 * setup.size_m.prod());
  // Mirrored about the centre's vertical planes: every node has its image.
  const Eigen::Vector3d centre(0.03, 0.03, 0.0);
  for (Eigen::Index i = 0; i < mesh.nodeCount(); ++i) {
    Eigen::Vector3d image = mesh.nodes_m.col(i);
    image.x() = 2.0 * centre.x() - image.x();
    image.y() = 2.0 * centre.y() - image.y();
    EXPECT_LT((mesh.nodes_m.colwise() - image).colwise().norm().minCoeff(), 1e-12) << i;
  }
  // The finest cells at the top centre: nodes 2.5 mm from the axis along x on the top face, and
  // 2.5 mm below it.
  const auto hasNode = [&](const Eigen::Vector3d& p) {
    return (mesh.nodes_m.colwise() - p).colwise().norm().minCoeff() < 1e-12;
  };
  EXPECT_TRUE(hasNode({0.03, 0.03, 0.03}));
  EXPECT_TRUE(hasNode({0.0325, 0.03, 0.03}));
  EXPECT_TRUE(hasNode({0.0275, 0.03, 0.03}));
  EXPECT_TRUE(hasNode({0.03, 0.03, 0.0275}));
  EXPECT_FALSE(hasNode({0.03, 0.03, 0.0025}));  // coarse at the bottom
}

TEST(IndentHapticRate, OnTheReferencesGridMirroredItGivesTheReferencesForce) {
  // The small block (10 x 10 x 5 mm) on the grid indentFem grades at refinement 2 (1.25 mm
  // cells at the probe), whole instead of a quarter, the probe's penalty on the quadratic
  // surface nodes as the reference's, pressed at 20 mm/s with an update each millisecond: the
  // quasi-static continuum, through the haptic-rate scheme, its bottom held and its depths below
  // the top face as the reference's.
  const StrainEnergy& energy = test::liverEnergy();
  const double kappa = defaultFemBulkModulus(energy);
  IndentationSetup setup;
  setup.size_m = {0.01, 0.01, 0.005};
  setup.depths_m = {0.00025, 0.0005};
  const IndentationCurve reference = indentFem(energy, setup, 2, kappa);
  HapticRateSettings settings;
  settings.speed_m_s = 0.02;
  settings.updateLatency_s = 0.001;
  settings.startAbove_m = 0.0002;
  const IndentationBodyGrading grading{setup.probeRadius_m / 2, kIndentationGrowth,
                                       kIndentationCoarsest_m};
  const HapticRatePoke poke = indentHapticRate(energy, setup, grading, kappa, 0.0, settings);
  ASSERT_EQ(poke.force_N.size(), 2u);
  for (std::size_t d = 0; d < 2; ++d) {
    ASSERT_GT(reference.force_N[d], 0.0);
    EXPECT_NEAR(poke.force_N[d] / reference.force_N[d], 1.0, 0.05) << d;
  }
  EXPECT_GT(poke.force_N[1], 2.0 * poke.force_N[0]);  // stiffening with depth
  EXPECT_EQ(poke.unconvergedSteps, 0);
  // The whole block: four times the quarter's tets.
  EXPECT_EQ(poke.elements, 4 * reference.elements);
  EXPECT_THROW(indentHapticRate(energy, setup, grading, kappa, -0.001, settings),
               std::invalid_argument);
  EXPECT_THROW(indentHapticRate(energy, setup, {0.001, 0.5, 0.008}, kappa, 0.0005, settings),
               std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
