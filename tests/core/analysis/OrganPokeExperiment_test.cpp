// SPDX-License-Identifier: Apache-2.0
// The organ poke's FEM reference: a block poked as an organ gives the indentation test's force,
// and what cannot be poked is refused.

#include "analysis/OrganPokeExperiment.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "fem/FemModel.h"
#include "mesh/BlockMesher.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

/// The indentation test's small block (10 x 10 x 5 mm, bottom held, probe at the top centre) as
/// an organ: a uniform grid of 1.25 mm cells, the bottom in the fixed box.
OrganPokeSetup smallBlockPoke() {
  OrganPokeSetup setup;
  setup.tipStart_m = {0.005, 0.005, 0.008};
  setup.direction = -Eigen::Vector3d::UnitZ();
  setup.fixedBox_m =
      Eigen::AlignedBox3d(Eigen::Vector3d(-1.0, -1.0, -1.0), Eigen::Vector3d(1.0, 1.0, 1e-9));
  setup.depths_m = {0.00025, 0.0005};
  return setup;
}

TEST(OrganPoke, ABlockPokedAsAnOrganGivesTheIndentationTestsForce) {
  // The same continuum discretised twice at the probe's scale (1.25 mm cells under it): the
  // whole block on a uniform grid, poked through the organ's surface, against the indentation
  // test's quarter block with symmetry planes on its grid graded from 1.25 mm.
  const StrainEnergy& energy = test::liverEnergy();
  const double kappa = defaultFemBulkModulus(energy);
  const TetMesh block = makeBlockMesh({0.01, 0.01, 0.005}, {8, 8, 4});
  const IndentationCurve organ = pokeOrganFem(energy, block, smallBlockPoke(), kappa);
  IndentationSetup indentation;
  indentation.size_m = {0.01, 0.01, 0.005};
  indentation.depths_m = {0.00025, 0.0005};
  const IndentationCurve reference = indentFem(energy, indentation, 2, kappa);
  ASSERT_EQ(organ.force_N.size(), 2u);
  EXPECT_EQ(organ.unconvergedPoints, 0);
  for (std::size_t d = 0; d < 2; ++d) {
    ASSERT_GT(reference.force_N[d], 0.0);
    EXPECT_NEAR(organ.force_N[d] / reference.force_N[d], 1.0, 0.05) << d;
  }
  EXPECT_GT(organ.force_N[1], 2.0 * organ.force_N[0]);  // stiffening with depth
  // Its cost: at least one Newton iteration a depth, timed within the whole run's time.
  EXPECT_GE(organ.newtonIterations, 2);
  EXPECT_GT(organ.solving_s, 0.0);
  EXPECT_LE(organ.solving_s, organ.seconds);
}

TEST(OrganPoke, WhatCannotBePokedIsRefused) {
  const StrainEnergy& energy = test::liverEnergy();
  const double kappa = defaultFemBulkModulus(energy);
  const TetMesh block = makeBlockMesh({0.01, 0.01, 0.005}, {2, 2, 1});
  OrganPokeSetup beside = smallBlockPoke();
  beside.tipStart_m.x() = 0.02;
  EXPECT_THROW(pokeOrganFem(energy, block, beside, kappa), std::invalid_argument);
  OrganPokeSetup unheld = smallBlockPoke();
  unheld.fixedBox_m =
      Eigen::AlignedBox3d(Eigen::Vector3d(1.0, 1.0, 1.0), Eigen::Vector3d(2.0, 2.0, 2.0));
  EXPECT_THROW(pokeOrganFem(energy, block, unheld, kappa), std::invalid_argument);
  OrganPokeSetup backwards = smallBlockPoke();
  backwards.depths_m = {0.0005, 0.00025};
  EXPECT_THROW(pokeOrganFem(energy, block, backwards, kappa), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
