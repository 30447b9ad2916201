// SPDX-License-Identifier: Apache-2.0
// The organ poke's FEM reference: a block poked as an organ gives the indentation test's force;
// the contact sampled between the nodes converges in its spacing; at the haptic rate it follows the
// static force where its updates come often enough, and lags where they do not; under its weight
// the body sags as a held column does and a tray holds it up; what cannot be poked is refused.

#include "analysis/OrganPokeExperiment.h"

#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

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

/// A coarse block (4 x 4 x 2 cells of 2.5 mm, 405 quadratic nodes) for the haptic-rate pokes.
TetMesh coarseBlock() { return makeBlockMesh({0.01, 0.01, 0.005}, {4, 4, 2}); }

OrganPokeSetup coarseSampledPoke() {
  OrganPokeSetup setup = smallBlockPoke();
  setup.depths_m = {0.0003, 0.0006};
  setup.contactSpacing_m = 0.0005;
  return setup;
}

TEST(OrganPoke, TheSampledContactConvergesInItsSpacingAndMeetsMoreThanTheNodes) {
  // On the coarse block (quadratic nodes 1.25 mm apart, the contact 1.6 to 2.2 mm across at 0.5
  // to 1 mm): the points between the nodes read the same 0.5 and 0.25 mm apart, and more than
  // the penalty on the nodes alone, which lets the probe sink between them.
  const StrainEnergy& energy = test::liverEnergy();
  const double kappa = defaultFemBulkModulus(energy);
  const TetMesh block = coarseBlock();
  std::vector<std::vector<double>> forces;
  for (const double spacing_m : {0.0, 0.0005, 0.00025}) {
    OrganPokeSetup setup = smallBlockPoke();
    setup.depths_m = {0.0005, 0.001};
    setup.contactSpacing_m = spacing_m;
    const IndentationCurve curve = pokeOrganFem(energy, block, setup, kappa);
    EXPECT_EQ(curve.unconvergedPoints, 0);
    forces.push_back(curve.force_N);
  }
  for (std::size_t d = 0; d < 2; ++d) {
    EXPECT_NEAR(forces[1][d] / forces[2][d], 1.0, 0.02) << d;
    EXPECT_GT(forces[2][d], 1.5 * forces[0][d]) << d;
  }
}

/// The coarse block's sampled poke statically, and at the haptic rate at 20 mm/s from 0.2 mm
/// above with each update answering latency_s after it starts.
struct HapticRateAgainstStatic {
  IndentationCurve still;
  HapticRatePoke poke;
  explicit HapticRateAgainstStatic(double latency_s) {
    const StrainEnergy& energy = test::liverEnergy();
    const double kappa = defaultFemBulkModulus(energy);
    const TetMesh block = coarseBlock();
    still = pokeOrganFem(energy, block, coarseSampledPoke(), kappa);
    HapticRateSettings settings;
    settings.speed_m_s = 0.02;
    settings.updateLatency_s = latency_s;
    settings.startAbove_m = 0.0002;
    poke = pokeOrganHapticRate(energy, block, coarseSampledPoke(), kappa, settings);
  }
};

TEST(OrganPoke, AtTheHapticRateWithFrequentUpdatesItFollowsTheStaticForce) {
  // 20 um of the probe's travel an update (an update answering in 1 ms): well within the
  // staggered iteration's reach, so each depth's force is the static one's.
  const HapticRateAgainstStatic run(0.001);
  const HapticRatePoke& poke = run.poke;
  EXPECT_EQ(poke.nodes, 405);
  ASSERT_EQ(poke.force_N.size(), 2u);
  for (std::size_t d = 0; d < 2; ++d) {
    ASSERT_GT(run.still.force_N[d], 0.0);
    EXPECT_NEAR(poke.force_N[d] / run.still.force_N[d], 1.0, 0.03) << d;
  }
  // Each millisecond a contact solve and an update: 40 of them to 0.6 mm from 0.2 mm above.
  EXPECT_EQ(poke.steps, static_cast<long>(poke.stepTimes_ms.size()));
  EXPECT_GE(poke.steps, 40);
  EXPECT_GE(poke.updates, poke.steps - 1);
  EXPECT_EQ(poke.unconvergedSteps, 0);
  EXPECT_EQ(poke.unsteppedUpdates, 0);
  EXPECT_GT(poke.maxCandidates, 3);
}

TEST(OrganPoke, AtTheHapticRateUpdatesFarApartLagBehindTheStaticForce) {
  // An update every 0.3 mm of the probe's travel: the contact answers with the body linearised
  // where it was, and the force at the first depth is not the static one.
  const HapticRateAgainstStatic run(0.015);
  ASSERT_EQ(run.poke.force_N.size(), 2u);
  EXPECT_GT(std::abs(run.poke.force_N[0] / run.still.force_N[0] - 1.0), 0.1);
}

/// A column 2 x 2 x 20 mm (2 x 2 x 10 cells), its foot in the fixed box, poked on its top
/// along -z; g along -z (m/s^2, 0: weightless).
OrganPokeSetup columnPoke(double g_m_s2) {
  OrganPokeSetup setup;
  setup.tipStart_m = {0.001, 0.001, 0.025};
  setup.direction = -Eigen::Vector3d::UnitZ();
  setup.fixedBox_m =
      Eigen::AlignedBox3d(Eigen::Vector3d(-1.0, -1.0, -1.0), Eigen::Vector3d(1.0, 1.0, 1e-9));
  setup.depths_m = {0.0001};
  setup.gravity_m_s2 = {0.0, 0.0, -g_m_s2};
  return setup;
}

TEST(OrganPoke, UnderItsWeightAHeldColumnSinksAsTheClosedFormSays) {
  // A slender column standing on its held foot sinks at its top by rho g H^2 / (2 E) under its
  // own weight, E = 3 mu0 for an incompressible solid at small strain (g kept small for it).
  // The probe then comes down on the top where it has settled.
  const StrainEnergy& energy = test::liverEnergy();
  const double kappa = defaultFemBulkModulus(energy);
  const double mu0_Pa = 2.0 * energy.secantFromRest(0.0).value;
  const TetMesh column = makeBlockMesh({0.002, 0.002, 0.02}, {2, 2, 10});
  const double g_m_s2 = 0.5;
  const IndentationCurve weighted = pokeOrganFem(energy, column, columnPoke(g_m_s2), kappa);
  const double closedForm_m = 1060.0 * g_m_s2 * 0.02 * 0.02 / (2.0 * 3.0 * mu0_Pa);
  ASSERT_GT(closedForm_m, 1e-5);
  EXPECT_NEAR(weighted.entrySag_m / closedForm_m, 1.0, 0.05);
  EXPECT_GT(weighted.settlingIterations, 0);
  EXPECT_EQ(weighted.unconvergedPoints, 0);
  ASSERT_EQ(weighted.force_N.size(), 1u);
  EXPECT_GT(weighted.force_N[0], 0.0);
  // Weightless, the top stays where it was.
  const IndentationCurve weightless = pokeOrganFem(energy, column, columnPoke(0.0), kappa);
  EXPECT_EQ(weightless.entrySag_m, 0.0);
  EXPECT_EQ(weightless.settlingIterations, 0);
}

TEST(OrganPoke, UnderItsWeightATrayHoldsTheBodyUp) {
  // The small block held along one side (a cantilever) sags under its weight; a tray 0.1 mm
  // under its bottom catches it: its top then sinks little more than that.
  const StrainEnergy& energy = test::liverEnergy();
  const double kappa = defaultFemBulkModulus(energy);
  const TetMesh block = makeBlockMesh({0.01, 0.01, 0.005}, {4, 4, 2});
  OrganPokeSetup hanging = smallBlockPoke();
  hanging.fixedBox_m =
      Eigen::AlignedBox3d(Eigen::Vector3d(-1.0, -1.0, -1.0), Eigen::Vector3d(1e-9, 1.0, 1.0));
  hanging.depths_m = {0.0001};
  hanging.gravity_m_s2 = {0.0, 0.0, -9.81};
  const IndentationCurve free = pokeOrganFem(energy, block, hanging, kappa);
  OrganPokeSetup onTray = hanging;
  onTray.tray = OrganPokeSetup::Tray{Eigen::Vector3d::UnitZ(), -0.0001, 3e7};
  const IndentationCurve held = pokeOrganFem(energy, block, onTray, kappa);
  ASSERT_GT(free.entrySag_m, 0.00025);
  EXPECT_GT(held.entrySag_m, 0.00005);
  EXPECT_LT(held.entrySag_m, 0.00015);
  // A tray needs a weight to press on it.
  OrganPokeSetup weightless = onTray;
  weightless.gravity_m_s2.setZero();
  EXPECT_THROW(pokeOrganFem(energy, block, weightless, kappa), std::invalid_argument);
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
  for (const auto& change : std::vector<std::function<void(HapticRateSettings&)>>{
           [](HapticRateSettings& s) { s.speed_m_s = 0.0; },
           [](HapticRateSettings& s) { s.hapticStep_s = -0.001; },
           [](HapticRateSettings& s) { s.updateLatency_s = -1.0; },
           [](HapticRateSettings& s) { s.candidateMargin_m = -0.001; },
           [](HapticRateSettings& s) { s.newtonIterations = -1; }}) {
    HapticRateSettings settings;
    change(settings);
    EXPECT_THROW(pokeOrganHapticRate(energy, block, smallBlockPoke(), kappa, settings),
                 std::invalid_argument);
  }
  EXPECT_THROW(pokeOrganHapticRate(energy, block, beside, kappa, {}), std::invalid_argument);
  OrganPokeSetup weighted = smallBlockPoke();  // the haptic-rate poke runs weightless
  weighted.gravity_m_s2 = {0.0, 0.0, -9.81};
  EXPECT_THROW(pokeOrganHapticRate(energy, block, weighted, kappa, {}), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
