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

SceneDescription bundledSceneWithFriction(double coefficient) {
  SceneDescription scene = bundledScene();
  scene.tray->friction = coefficient;
  return scene;
}

/// The mean sideways (x) travel of the drawn surface's points that rest on the tray at the
/// start, after `steps` steps with gravity tipped sideways by a third of g.
double lobeSlide_m(Simulation& simulation, int steps) {
  const TraySupport& tray = *simulation.tray();
  const Eigen::Matrix3Xd start = simulation.state().x;
  simulation.setGravity({9.81 / 3.0, -9.81, 0.0});
  for (int n = 0; n < steps; ++n) EXPECT_TRUE(simulation.step().isGood) << n;
  simulation.setGravity({0.0, -9.81, 0.0});
  double slide = 0.0;
  int resting = 0;
  for (const CarriedSurfacePoint& point : tray.points()) {
    if (!(tray.up().dot(point.drawn(start)) < tray.height_m())) continue;
    slide += point.drawn(simulation.state().x).x() - point.drawn(start).x();
    ++resting;
  }
  EXPECT_GT(resting, 0);
  return slide / resting;
}

TEST(SettledStart, OnATrayWithFrictionTheLiverSettlesStaysAndResetsToItsGrip) {
  Simulation simulation(bundledSceneWithFriction(0.3));
  EXPECT_TRUE(simulation.events().empty());
  ASSERT_NE(simulation.trayFriction(), nullptr);
  int anchored = 0;
  for (const PlaneFriction::Anchor& anchor : simulation.trayFriction()->anchors())
    anchored += anchor.limit_N > 0.0 ? 1 : 0;
  EXPECT_GT(anchored, 0) << "the lobe grips the tray where it came to rest";
  const MechanicalState start = simulation.state();
  const std::vector<PlaneFriction::Anchor> settled = simulation.trayFriction()->anchors();
  for (int n = 0; n < 1000; ++n) ASSERT_TRUE(simulation.step().isGood) << n;
  EXPECT_LT(largestDistance_m(simulation.state().x, start.x), 5e-5);
  EXPECT_TRUE(simulation.events().empty());
  // Pulled sideways, the lobe slides and its grip moves with it; reset puts back the grip that
  // settling left.
  const auto anchorsEqual = [](const std::vector<PlaneFriction::Anchor>& a,
                               const std::vector<PlaneFriction::Anchor>& b) {
    for (std::size_t p = 0; p < a.size(); ++p) {
      if (a[p].limit_N != b[p].limit_N || a[p].position_m != b[p].position_m) return false;
    }
    return a.size() == b.size();
  };
  EXPECT_NE(lobeSlide_m(simulation, 300), 0.0);
  EXPECT_FALSE(anchorsEqual(simulation.trayFriction()->anchors(), settled));
  simulation.reset();
  EXPECT_TRUE(anchorsEqual(simulation.trayFriction()->anchors(), settled));
  EXPECT_EQ(simulation.state().x, start.x);
}

TEST(SettledStart, FrictionHoldsTheLobeOnTheTrayAgainstASidewaysPull) {
  // The liver tipped a third of g sideways for 0.3 s: on a frictionless tray its lowest lobe
  // slides over it by millimetres; with friction 1 it stays put, within the ties' elastic reach.
  // (The tray carries 1.3 N of the liver's 11 N: at 0.3 the lobe slides much as it does without.)
  Simulation frictionless(bundledScene());
  Simulation gripped(bundledSceneWithFriction(1.0));
  const double slid_m = lobeSlide_m(frictionless, 300);
  const double held_m = lobeSlide_m(gripped, 300);
  EXPECT_GT(slid_m, 3e-3);
  EXPECT_LT(std::abs(held_m), 0.05 * slid_m);
  EXPECT_TRUE(gripped.events().empty());
}

}  // namespace
}  // namespace tissuesim
