// SPDX-License-Identifier: Apache-2.0
// The FEM at its own rate refined again where the tool aims (Simulation::refineTowardsTool): the
// body made again is the one the scene would have made with its tool started there, the session
// goes on, and the body is made again only while nothing touches it and the tool aims elsewhere.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sim/HapticRateBody.h"
#include "sim/InstrumentScript.h"
#include "sim/SceneFile.h"
#include "sim/Simulation.h"

namespace tissuesim {
namespace {

SceneDescription refinedScene() {
  return loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-fem-refined.json");
}

/// Above the liver's upper face 4 cm along x from the scene's start (the second poke site of
/// docs/performance-details.md), the tool pointing down as the scene's.
const Eigen::Vector3d kSecondSite_m(-0.04, 0.152, 0.045);

/// Steps `simulation` along `keyframes` (times from its time now) to their end.
void follow(Simulation& simulation, std::vector<InstrumentScript::Keyframe> keyframes) {
  const long steps = std::lround(keyframes.back().time_s / simulation.timeStep_s());
  for (InstrumentScript::Keyframe& keyframe : keyframes) keyframe.time_s += simulation.time_s();
  const InstrumentScript script(keyframes);
  simulation.setInstrumentSource(&script);
  for (long n = 0; n < steps; ++n) ASSERT_TRUE(simulation.step().isGood) << n;
  simulation.setInstrumentSource(nullptr);
}

/// The tool pressed 3 mm past where its axis meets the organ and back at 10 mm/s, from where it
/// is: each step's force along the axis.
std::vector<double> pokeFromHere(Simulation& simulation) {
  const InstrumentPose here = simulation.instrumentPose();
  Eigen::Vector3d entry;
  EXPECT_TRUE(firstOrganCrossing(simulation.geometry(), here.tip_m, here.direction, entry));
  const double depth_m = (entry - here.tip_m).dot(here.direction) + 0.003;
  std::vector<InstrumentScript::Keyframe> keyframes =
      InstrumentScript::poke(here, depth_m, depth_m / 0.01).keyframes();
  const long steps = std::lround(keyframes.back().time_s / simulation.timeStep_s());
  for (InstrumentScript::Keyframe& keyframe : keyframes) keyframe.time_s += simulation.time_s();
  const InstrumentScript script(keyframes);
  simulation.setInstrumentSource(&script);
  std::vector<double> force_N;
  for (long n = 0; n < steps; ++n) {
    const StepOutcome outcome = simulation.step();
    EXPECT_TRUE(outcome.isGood) << n;
    force_N.push_back(outcome.contact.toolForce_N.dot(-here.direction));
  }
  simulation.setInstrumentSource(nullptr);
  return force_N;
}

TEST(RefinedTowardsTool, TheBodyMadeAgainIsTheOneTheSceneMakesWithItsToolStartedThere) {
  const SceneDescription scene = refinedScene();
  const InstrumentPose start{scene.instrument->tipStart_m, scene.instrument->direction, false};
  const InstrumentPose second{kSecondSite_m, scene.instrument->direction, false};
  Simulation moved(scene);
  ASSERT_TRUE(moved.refinementCentre().has_value());
  const Eigen::Vector3d firstCentre = *moved.refinementCentre();
  // Pressed where the scene starts it first: the session's figures to carry on.
  const std::vector<double> firstPoke = pokeFromHere(moved);
  ASSERT_GT(*std::max_element(firstPoke.begin(), firstPoke.end()), 0.01);
  const double peakStretch = moved.assessment().summary().largestStretch;
  EXPECT_FALSE(moved.wantsRefinementTowardsTool());  // aimed where it was refined
  // Across to the second site in 0.5 s and held there 0.3 s, clear of the organ.
  follow(moved, {{0.0, start}, {0.5, second}, {0.8, second}});
  ASSERT_TRUE(moved.wantsRefinementTowardsTool());
  const long steps = moved.steps();
  const Eigen::Index nodesBefore = moved.geometry().mesh.nodeCount();
  ASSERT_TRUE(moved.refineTowardsTool());
  EXPECT_EQ(moved.refinements(), 1);
  EXPECT_FALSE(moved.wantsRefinementTowardsTool());
  EXPECT_GT((*moved.refinementCentre() - firstCentre).norm(), 0.035);
  EXPECT_NE(moved.geometry().mesh.nodeCount(), nodesBefore);
  // The session goes on: its clock, and the stretch the first poke reached.
  EXPECT_EQ(moved.steps(), steps);
  EXPECT_NEAR(moved.assessment().summary().duration_s, moved.time_s(), 1e-9);
  EXPECT_DOUBLE_EQ(moved.assessment().summary().largestStretch, peakStretch);
  EXPECT_EQ(moved.state().x.cols(), moved.geometry().mesh.nodeCount());

  // The scene opened with its tool at the second site makes the same mesh and body.
  SceneDescription there = scene;
  there.instrument->tipStart_m = kSecondSite_m;
  Simulation opened(there);
  ASSERT_EQ(opened.geometry().mesh.nodeCount(), moved.geometry().mesh.nodeCount());
  EXPECT_EQ(opened.geometry().mesh.tets, moved.geometry().mesh.tets);
  EXPECT_EQ((opened.geometry().mesh.nodes_m - moved.geometry().mesh.nodes_m).cwiseAbs().maxCoeff(),
            0.0);
  EXPECT_LT((opened.state().x - moved.state().x).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((*opened.refinementCentre() - *moved.refinementCentre()).norm(), 1e-12);
  // And both feel the same poke there, where nothing has been pressed before (the first press
  // leaves its softening in the body made again: WhatAPokeSoftenedStaysSoftInTheBodyMadeAgain).
  Simulation unpressed(scene);
  follow(unpressed, {{0.0, start}, {0.5, second}, {0.8, second}});
  ASSERT_TRUE(unpressed.refineTowardsTool());
  const std::vector<double> movedForce = pokeFromHere(unpressed);
  const std::vector<double> openedForce = pokeFromHere(opened);
  ASSERT_EQ(movedForce.size(), openedForce.size());
  double peak_N = 0.0, largestDifference_N = 0.0;
  for (std::size_t n = 0; n < movedForce.size(); ++n) {
    peak_N = std::max(peak_N, openedForce[n]);
    largestDifference_N = std::max(largestDifference_N, std::abs(movedForce[n] - openedForce[n]));
  }
  ASSERT_GT(peak_N, 0.01);
  EXPECT_LT(largestDifference_N, 1e-9 * peak_N);
  EXPECT_TRUE(moved.events().empty());
  EXPECT_TRUE(unpressed.events().empty());
}

TEST(RefinedTowardsTool, TheBodyIsMadeAgainOnlyWhileNothingTouchesItAndTheToolAimsElsewhere) {
  const SceneDescription scene = refinedScene();
  const InstrumentPose start{scene.instrument->tipStart_m, scene.instrument->direction, false};
  Simulation simulation(scene);
  // A few millimetres aside: still where the body was refined.
  InstrumentPose near = start;
  near.tip_m.x() -= 0.5 * Simulation::kRefineAgainDistance_m;
  follow(simulation, {{0.0, start}, {0.2, near}, {0.3, near}});
  EXPECT_FALSE(simulation.wantsRefinementTowardsTool());
  // Pressing 2 mm into the organ 1 cm aside: aimed elsewhere, but touching it.
  InstrumentPose aside = start;
  aside.tip_m.x() -= 0.01;
  Eigen::Vector3d entry;
  ASSERT_TRUE(firstOrganCrossing(simulation.geometry(), aside.tip_m, aside.direction, entry));
  InstrumentPose pressing = aside;
  pressing.tip_m = entry + 0.002 * aside.direction;  // the round end's point
  follow(simulation, {{0.0, near}, {0.2, aside}, {2.5, pressing}, {2.8, pressing}});
  EXPECT_GT(simulation.assessment().summary().peakToolForce_N, 0.01);
  EXPECT_FALSE(simulation.wantsRefinementTowardsTool());
  EXPECT_FALSE(simulation.hapticRateBody()->isAtRest());
  // Drawn back out and clear: the body springs back to rest, and is made again there.
  follow(simulation, {{0.0, pressing}, {2.5, aside}, {3.0, aside}});
  EXPECT_TRUE(simulation.hapticRateBody()->isAtRest());
  EXPECT_TRUE(simulation.wantsRefinementTowardsTool());
  // Aimed past the organ: nothing to refine towards, nothing changes.
  InstrumentPose past = aside;
  past.tip_m.x() += 0.5;
  follow(simulation, {{0.0, aside}, {0.2, past}, {0.3, past}});
  EXPECT_FALSE(simulation.wantsRefinementTowardsTool());
  const Eigen::Index nodes = simulation.geometry().mesh.nodeCount();
  EXPECT_FALSE(simulation.refineTowardsTool());
  EXPECT_EQ(simulation.geometry().mesh.nodeCount(), nodes);
  EXPECT_EQ(simulation.refinements(), 0);
  EXPECT_TRUE(simulation.events().empty());
}

TEST(RefinedTowardsTool, TheBodyIsMadeAgainFromTheFilesAsTheSceneOpenedThem) {
  // The scene and its files copied aside, opened, then its meshes deleted: the body is made
  // again all the same, from what was read as the scene opened.
  const std::filesystem::path assets(TISSUESIM_ASSET_DIR);
  const std::filesystem::path copy =
      std::filesystem::temp_directory_path() / "tissuesim-refined-files-test";
  std::filesystem::remove_all(copy);
  for (const char* file : {"scenes/liver-fem-refined.json", "tissues/porcine-liver.json",
                           "meshes/liver-smooth.obj", "meshes/liver-haptic-24mm.msh"}) {
    std::filesystem::create_directories((copy / file).parent_path());
    std::filesystem::copy_file(assets / file, copy / file);
  }
  const SceneDescription scene = loadSceneFile(copy / "scenes/liver-fem-refined.json");
  Simulation simulation(scene);
  std::filesystem::remove_all(copy / "meshes");
  const InstrumentPose start{scene.instrument->tipStart_m, scene.instrument->direction, false};
  const InstrumentPose second{kSecondSite_m, scene.instrument->direction, false};
  follow(simulation, {{0.0, start}, {0.5, second}, {0.8, second}});
  ASSERT_TRUE(simulation.wantsRefinementTowardsTool());
  EXPECT_TRUE(simulation.refineTowardsTool());
  EXPECT_EQ(simulation.refinements(), 1);
  std::filesystem::remove_all(copy);
}

TEST(RefinedTowardsTool, WhatAPokeSoftenedStaysSoftInTheBodyMadeAgain) {
  // Pressed 3 mm where the scene starts the tool, then taken to the second site (the body made
  // again there) and back (made again where it started): pressed again, it is softer below the
  // first press's peak (the Mullins effect), as in a body never made again, not the virgin tissue.
  const SceneDescription scene = refinedScene();
  const InstrumentPose start{scene.instrument->tipStart_m, scene.instrument->direction, false};
  const InstrumentPose second{kSecondSite_m, scene.instrument->direction, false};
  Simulation travelled(scene);
  const std::vector<double> first = pokeFromHere(travelled);
  follow(travelled, {{0.0, start}, {0.5, second}, {0.8, second}});
  ASSERT_TRUE(travelled.wantsRefinementTowardsTool());
  ASSERT_TRUE(travelled.refineTowardsTool());
  follow(travelled, {{0.0, second}, {0.5, start}, {0.8, start}});
  ASSERT_TRUE(travelled.wantsRefinementTowardsTool());
  ASSERT_TRUE(travelled.refineTowardsTool());
  const std::vector<double> again = pokeFromHere(travelled);
  // The same two presses with the body kept.
  Simulation kept(scene);
  const std::vector<double> keptFirst = pokeFromHere(kept);
  follow(kept, {{0.0, start}, {0.5, second}, {0.8, second}, {1.3, start}, {1.6, start}});
  const std::vector<double> keptAgain = pokeFromHere(kept);
  ASSERT_EQ(first.size(), again.size());
  ASSERT_EQ(keptFirst, first);
  // Halfway up the first press's force, on the way in.
  const double peak_N = *std::max_element(first.begin(), first.end());
  ASSERT_GT(peak_N, 0.05);
  std::size_t half = 0;
  while (first[half] < 0.5 * peak_N) ++half;
  EXPECT_LT(again[half], 0.97 * first[half]);  // the virgin tissue would read the first's
  EXPECT_NEAR(again[half] / keptAgain[half], 1.0, 0.01);
  EXPECT_TRUE(travelled.events().empty());
}

TEST(RefinedTowardsTool, AScenesBodyNotRefinedTowardsTheToolIsNeverMadeAgain) {
  const SceneDescription scene =
      loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-fem-haptic-rate.json");
  Simulation simulation(scene);
  EXPECT_FALSE(simulation.refinementCentre().has_value());
  const InstrumentPose start{scene.instrument->tipStart_m, scene.instrument->direction, false};
  InstrumentPose second{kSecondSite_m, scene.instrument->direction, false};
  follow(simulation, {{0.0, start}, {0.3, second}, {0.5, second}});
  EXPECT_FALSE(simulation.wantsRefinementTowardsTool());
  EXPECT_FALSE(simulation.refineTowardsTool());
}

}  // namespace
}  // namespace tissuesim
