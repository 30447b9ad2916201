// SPDX-License-Identifier: Apache-2.0
// A scene with gravity opens settled on its supports, stays there, and resets to it: the
// bundled liver, on its tray.
#include <gtest/gtest.h>

#include "sim/SceneFile.h"
#include "sim/Simulation.h"

namespace tissuesim {
namespace {

SceneDescription bundledScene() {
  return loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json");
}

double largestDistance_m(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return (a - b).colwise().norm().maxCoeff();
}

TEST(SettledStart, TheLiverOpensSaggedOntoItsTrayAndStaysThere) {
  Simulation simulation(bundledScene());
  const MechanicalState start = simulation.state();
  EXPECT_TRUE(simulation.events().empty());
  // It has sagged under its weight (the mesh is the unloaded shape) and is still.
  EXPECT_GT(largestDistance_m(start.x, simulation.springMesh().restPositions_m), 0.005);
  EXPECT_EQ(start.v.cwiseAbs().maxCoeff(), 0.0);
  // Its lowest lobe rests on the tray: the tray carries part of the weight (the hold the rest),
  // and the drawn surface sinks into it by under a millimetre.
  ASSERT_NE(simulation.tray(), nullptr);
  const double weight_N = simulation.springMesh().nodeMass_kg.sum() * 9.81;
  const double carried_N = simulation.tray()->force_N(start.x).y();
  EXPECT_GT(carried_N, 0.05 * weight_N);
  EXPECT_LT(carried_N, weight_N);
  EXPECT_GT(simulation.tray()->maxPenetration_m(start.x), 0.0);
  EXPECT_LT(simulation.tray()->maxPenetration_m(start.x), 0.001);
  // A second of real-time steps: no drift, no creep, nothing reported.
  for (int n = 0; n < 1000; ++n) ASSERT_TRUE(simulation.step().isGood) << n;
  EXPECT_LT(largestDistance_m(simulation.state().x, start.x), 5e-5);
  EXPECT_LT(simulation.state().v.colwise().norm().maxCoeff(), 1e-3);
  EXPECT_TRUE(simulation.events().empty());
}

TEST(SettledStart, WithoutItsSupportsTheLiverWouldFallAndResetReturnsToTheSettledState) {
  Simulation simulation(bundledScene());
  const MechanicalState start = simulation.startState();
  const Eigen::VectorXd startMemory = simulation.springs().lambdaMax();
  // Gravity tripled for half a second: it sags further and its springs remember it.
  simulation.setGravity({0.0, -3.0 * 9.81, 0.0});
  for (int n = 0; n < 500; ++n) ASSERT_TRUE(simulation.step().isGood) << n;
  EXPECT_GT(largestDistance_m(simulation.state().x, start.x), 0.005);
  EXPECT_GT((simulation.springs().lambdaMax() - startMemory).maxCoeff(), 0.0);
  simulation.setGravity({0.0, -9.81, 0.0});
  simulation.reset();
  EXPECT_EQ(simulation.state().x, start.x);
  EXPECT_EQ(simulation.state().v, start.v);
  EXPECT_EQ(simulation.springs().lambdaMax(), startMemory);
}

TEST(SettledStart, WithoutGravityTheSceneStartsAtTheMeshsShape) {
  SceneDescription scene = bundledScene();
  scene.gravity_m_s2.setZero();
  const Simulation simulation(scene);
  EXPECT_EQ(simulation.state().x, simulation.springMesh().restPositions_m);
  EXPECT_TRUE(simulation.events().empty());
}

TEST(SettledStart, AnOrganNothingHoldsIsReportedAndStartsUnloaded) {
  // No tray and no fixed node: it falls for ever; the simulation says so and starts unloaded.
  SceneDescription scene = bundledScene();
  scene.tray.reset();
  scene.fixed = {};
  const Simulation simulation(scene);
  ASSERT_EQ(simulation.events().size(), 1u);
  EXPECT_EQ(simulation.events()[0].kind, "unsettled");
  EXPECT_NE(simulation.events()[0].detail.find("did not come to rest"), std::string::npos);
  EXPECT_EQ(simulation.state().x, simulation.springMesh().restPositions_m);
}

}  // namespace
}  // namespace tissuesim
