// The fixed-step simulation of a scene with the FCL contact: a poke of the bundled liver.

#include "sim/Simulation.h"

#include <gtest/gtest.h>

#include "CapsuleContact.h"
#include "sim/SceneFile.h"

namespace tissuesim {
namespace {

struct PokeRun {
  std::vector<double> forces;
  Eigen::Matrix3Xd finalPositions;
  std::size_t events = 0;
};

PokeRun poke(int steps) {
  Simulation simulation(loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json"));
  const SceneInstrument& tool = *simulation.scene().instrument;
  const InstrumentScript script = InstrumentScript::poke({tool.tipStart_m, tool.direction}, 0.04, 1.0);
  CapsuleContact contact(simulation.geometry().mesh, {tool.shaftRadius_m, tool.shaftLength_m});
  simulation.setContactProvider(&contact);
  simulation.setInstrumentSource(&script);
  PokeRun run;
  for (int n = 0; n < steps; ++n) {
    const StepOutcome outcome = simulation.step();
    EXPECT_TRUE(outcome.isGood) << "step " << n;
    run.forces.push_back(outcome.contact.toolForce_N.norm());
  }
  run.finalPositions = simulation.state().x;
  run.events = simulation.events().size();
  return run;
}

TEST(Simulation, APokeTouchesPushesAndIsDeterministic) {
  const PokeRun first = poke(600);
  // The tip starts 1.7 cm above the liver's top and comes down at 4 cm/s: no force before
  // about 0.4 s, then a push that grows as it goes deeper.
  for (int n = 0; n < 350; ++n) EXPECT_EQ(first.forces[static_cast<std::size_t>(n)], 0.0) << n;
  EXPECT_GT(first.forces.back(), 0.05);
  double early = 0.0, late = 0.0;
  for (int n = 450; n < 500; ++n) early += first.forces[static_cast<std::size_t>(n)];
  for (int n = 550; n < 600; ++n) late += first.forces[static_cast<std::size_t>(n)];
  EXPECT_GT(late, early);
  const PokeRun second = poke(600);
  EXPECT_EQ(first.forces, second.forces);  // bit-identical
  EXPECT_EQ(first.finalPositions, second.finalPositions);
}

TEST(Simulation, NonFiniteContactIsReportedAndTheStateKept) {
  Simulation simulation(loadSceneFile(std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json"));
  struct BrokenContact final : ContactProvider {
    ContactResult addContactForces(const Eigen::Matrix3Xd&, const Eigen::Matrix3Xd&, const InstrumentPose&,
                                   Eigen::Matrix3Xd& forces) override {
      forces(0, 0) = std::numeric_limits<double>::quiet_NaN();
      return {};
    }
  } broken;
  simulation.setContactProvider(&broken);
  const Eigen::Matrix3Xd before = simulation.state().x;
  const StepOutcome outcome = simulation.step();
  EXPECT_FALSE(outcome.isGood);
  EXPECT_EQ(simulation.state().x, before);
  ASSERT_FALSE(simulation.events().empty());
  EXPECT_EQ(simulation.steps(), 0);
  simulation.setContactProvider(nullptr);  // the program stays usable
  EXPECT_TRUE(simulation.step().isGood);
  EXPECT_EQ(simulation.steps(), 1);
}

}  // namespace
}  // namespace tissuesim
