// SPDX-License-Identifier: Apache-2.0
// The indentation test at the haptic rate: the block's body fills the block, fine at the top
// face's centre and coarse elsewhere, and the block pressed at the haptic rate on a fine body
// gives the reference's force.

#include "analysis/IndentationHapticRate.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "fem/FemModel.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

/// The shortest and the longest edge of `mesh`'s tets with a corner within radius_m of point_m.
Eigen::Vector2d edgeRangeNear(const TetMesh& mesh, const Eigen::Vector3d& point_m,
                              double radius_m) {
  Eigen::Vector2d range(1e9, 0.0);
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    bool isNear = false;
    for (int a = 0; a < 4; ++a)
      isNear = isNear || (mesh.nodes_m.col(mesh.tets(a, t)) - point_m).norm() < radius_m;
    if (!isNear) continue;
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        const double edge =
            (mesh.nodes_m.col(mesh.tets(a, t)) - mesh.nodes_m.col(mesh.tets(b, t))).norm();
        range = {std::min(range[0], edge), std::max(range[1], edge)};
      }
    }
  }
  return range;
}

TEST(IndentationBody, ItFillsTheBlockFineAtTheTopCentreAndCoarseAwayFromIt) {
  IndentationSetup setup;  // 60 x 60 x 30 mm
  const IndentationBodyGrading grading;
  const TetMesh body = indentationBody(setup, grading);
  const Eigen::Vector3d low = body.nodes_m.rowwise().minCoeff();
  const Eigen::Vector3d high = body.nodes_m.rowwise().maxCoeff();
  EXPECT_LT(low.norm(), 1e-15);
  EXPECT_LT((high - setup.size_m).norm(), 1e-15);
  double volume_m3 = 0.0;
  for (Eigen::Index t = 0; t < body.tetCount(); ++t) {
    const double v = signedTetVolume(body.nodes_m, body.tets, t);
    EXPECT_GT(v, 0.0) << t;
    volume_m3 += v;
  }
  EXPECT_NEAR(volume_m3, setup.size_m.prod(), 1e-12 * setup.size_m.prod());
  // Under the probe every edge within the grading's size there (finest + growth * distance at
  // the edge's middle, within 1 mm of the centre: at most 3 mm)...
  const Eigen::Vector3d centre(0.03, 0.03, 0.03);
  EXPECT_LT(edgeRangeNear(body, centre, 0.001)[1], 0.003 + 1e-12);
  // ...and at the bottom's corners the coarse block's cubes, untouched (15 mm edges, 21 mm face
  // diagonals).
  EXPECT_GT(edgeRangeNear(body, Eigen::Vector3d::Zero(), 0.001)[0], 0.015 - 1e-12);
  EXPECT_THROW(indentationBody(setup, {0.0015, 1.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(indentationBody(setup, {0.0, 1.0, 0.015}), std::invalid_argument);
}

TEST(IndentHapticRate, OnAFineBodyItGivesTheReferencesForce) {
  // The small block (10 x 10 x 5 mm) in 2.5 mm cubes refined to 0.625 mm edges under the probe,
  // pressed at 20 mm/s with an update each millisecond, the probe's penalty on the quadratic
  // surface nodes as the reference's: the quasi-static continuum through the haptic-rate
  // scheme, its bottom held and its depths below the top face as the reference's (its quarter
  // block graded from 0.625 mm, refinement 4).
  const StrainEnergy& energy = test::liverEnergy();
  const double kappa = defaultFemBulkModulus(energy);
  IndentationSetup setup;
  setup.size_m = {0.01, 0.01, 0.005};
  setup.depths_m = {0.00025, 0.0005};
  const IndentationCurve reference = indentFem(energy, setup, 4, kappa);
  HapticRateSettings settings;
  settings.speed_m_s = 0.02;
  settings.updateLatency_s = 0.001;
  settings.startAbove_m = 0.0002;
  const IndentationBodyGrading grading{0.000625, 1.0, 0.0025};
  const HapticRatePoke poke = indentHapticRate(energy, setup, grading, kappa, 0.0, settings);
  ASSERT_EQ(poke.force_N.size(), 2u);
  for (std::size_t d = 0; d < 2; ++d) {
    ASSERT_GT(reference.force_N[d], 0.0);
    EXPECT_NEAR(poke.force_N[d] / reference.force_N[d], 1.0, 0.05) << d;
  }
  EXPECT_GT(poke.force_N[1], 2.0 * poke.force_N[0]);  // stiffening with depth
  EXPECT_EQ(poke.unconvergedSteps, 0);
  EXPECT_THROW(indentHapticRate(energy, setup, grading, kappa, -0.001, settings),
               std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
