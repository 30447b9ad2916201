// SPDX-License-Identifier: Apache-2.0
// The soak's random session: reproducible from its seed, within the bounds it states, and never
// dragging the tool through the organ between pokes.
#include "sim/RandomSession.h"

#include <gtest/gtest.h>

#include "sim/SceneFile.h"

namespace tissuesim {
namespace {

const Simulation& bundledLiver() {
  static const Simulation simulation(
      loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json"));
  return simulation;
}

TEST(RandomSession, OneSeedOneSessionAnotherSeedAnother) {
  const InstrumentScript a = randomSession(bundledLiver(), 20.0, 7);
  const InstrumentScript b = randomSession(bundledLiver(), 20.0, 7);
  const InstrumentScript c = randomSession(bundledLiver(), 20.0, 8);
  EXPECT_GE(a.duration_s(), 20.0);
  bool differs = false;
  for (double t = 0.0; t < 20.0; t += 0.01) {
    EXPECT_EQ(a.poseAt(t).tip_m, b.poseAt(t).tip_m) << t;
    differs = differs || a.poseAt(t).tip_m != c.poseAt(t).tip_m;
  }
  EXPECT_TRUE(differs);
}

TEST(RandomSession, PokesGraspsAndTravelsAboveTheOrgan) {
  const Simulation& liver = bundledLiver();
  const InstrumentScript session = randomSession(liver, 60.0, 3);
  const Eigen::Matrix3Xd& x = liver.state().x;
  const double top = x.row(1).maxCoeff();
  const double bottom = x.row(1).minCoeff();
  int grasps = 0;
  bool wasGrasping = false;
  double lowest = top, highest = -1.0, fastest = 0.0;
  Eigen::Vector3d previous = session.poseAt(0.0).tip_m;
  for (double t = 1e-3; t < session.duration_s(); t += 1e-3) {
    const InstrumentPose pose = session.poseAt(t);
    grasps += pose.isGrasping && !wasGrasping ? 1 : 0;
    wasGrasping = pose.isGrasping;
    lowest = std::min(lowest, pose.tip_m.y());
    highest = std::max(highest, pose.tip_m.y());
    fastest = std::max(fastest, (pose.tip_m - previous).norm() / 1e-3);
    previous = pose.tip_m;
    // A shaft at most 30 degrees off vertical, pointing down.
    EXPECT_LT(pose.direction.y(), -std::cos(30.5 * 3.14159265358979 / 180.0) + 1e-9) << t;
  }
  EXPECT_GT(grasps, 5);                             // one cycle in three
  EXPECT_LT(lowest, top - 0.02);                    // it goes into the liver
  EXPECT_GT(lowest, bottom);                        // but not through it
  EXPECT_GT(highest, top + 0.04);                   // transits above it
  EXPECT_GT(fastest, 0.5);                          // fast pokes among the slow
  EXPECT_LT(fastest, 1.5 * 1.01 * std::sqrt(2.0));  // (a pose's speed is the press speed, or a
                                                    // transit's: below it)
}

TEST(RandomSession, ASceneWithoutAnInstrumentIsRefused) {
  SceneDescription scene =
      loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json");
  scene.instrument.reset();
  const Simulation simulation(scene);
  EXPECT_THROW(randomSession(simulation, 10.0, 1), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
