// SPDX-License-Identifier: Apache-2.0
#include "sim/RealTimeLoop.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include <gtest/gtest.h>

#include "forces/ContactProvider.h"
#include "sim/SceneFile.h"

namespace tissuesim {
namespace {

std::string bundledScenePath() {
  return std::string(TISSUESIM_ASSET_DIR) + "/scenes/liver-poke.json";
}

TEST(TripleBuffer, TheReaderNeverSeesAHalfWrittenValue) {
  struct Value {
    std::array<long, 64> words{};
  };
  TripleBuffer<Value> buffer;
  constexpr long kLast = 200000;
  std::thread writer([&] {
    for (long n = 1; n <= kLast; ++n) {
      buffer.back().words.fill(n);
      buffer.publish();
    }
  });
  // Read until the last value arrives: it always does, since the final publish stays fresh
  // until taken, however the two threads interleave.
  long last = 0;
  long updates = 0;
  while (last != kLast) {
    if (!buffer.update()) continue;
    ++updates;
    const Value& value = buffer.front();
    for (const long word : value.words) ASSERT_EQ(word, value.words[0]);
    ASSERT_GE(value.words[0], last);  // never older than what was already seen
    last = value.words[0];
  }
  writer.join();
  EXPECT_GE(updates, 1);
}

/// Runs a real-time loop on `simulation` for `duration` of wall time; its statistics.
LoopStatistics runLoopFor(Simulation& simulation, std::chrono::milliseconds duration) {
  RealTimeLoop loop(simulation);
  loop.start();
  std::this_thread::sleep_for(duration);
  loop.stop();
  return loop.statistics();
}

TEST(RealTimeLoop, RunsAtItsRateAndPublishesSnapshots) {
  Simulation simulation(loadSceneFile(bundledScenePath()));
  LiveInstrument instrument(simulation.instrumentPose());
  simulation.setInstrumentSource(&instrument);
  RealTimeLoop loop(simulation);
  loop.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  InstrumentPose moved =
      simulation.scene().instrument
          ? InstrumentPose{simulation.scene().instrument->tipStart_m + Eigen::Vector3d(0, 0.01, 0),
                           {0, -1, 0},
                           false}
          : InstrumentPose{};
  instrument.setPose(moved);  // from this (the GUI's) thread while the physics runs
  // Wait for a snapshot that holds the move, ten steps in: at 1 kHz within milliseconds, but
  // under ThreadSanitizer on a loaded machine a step can take tens of them.
  const SimulationSnapshot* snapshot = &loop.snapshot();
  for (int n = 0; n < 300 && !(snapshot->step > 10 &&
                               std::abs(snapshot->instrument.tip_m.y() - moved.tip_m.y()) <= 1e-12);
       ++n) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    snapshot = &loop.snapshot();
  }
  loop.stop();
  const LoopStatistics statistics = loop.statistics();
  EXPECT_GT(statistics.steps, 10);
  EXPECT_GT(statistics.realtimeFactor(), 0.0);
  EXPECT_LE(statistics.realtimeFactor(), 1.05);  // paced: never faster than real time
  EXPECT_GT(snapshot->step, 10);
  EXPECT_EQ(snapshot->positions_m.cols(), simulation.state().x.cols());
  EXPECT_TRUE(snapshot->positions_m.allFinite());
  EXPECT_NEAR(snapshot->instrument.tip_m.y(), moved.tip_m.y(), 1e-12);
}

TEST(RealTimeLoop, ABeforeStepCallThatSaysNoEndsTheLoopBeforeThatStep) {
  // A replay's end: the call before step 5 says no, so the loop ends after exactly 4 steps and
  // says it is not running; started again, it runs on.
  Simulation simulation(loadSceneFile(bundledScenePath()));
  RealTimeLoop loop(simulation);
  std::atomic<int> calls{0};
  loop.setBeforeStep([&] { return ++calls <= 4; });
  loop.start();
  for (int n = 0; n < 500 && loop.isRunning(); ++n)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  EXPECT_FALSE(loop.isRunning());
  EXPECT_EQ(calls.load(), 5);
  EXPECT_EQ(simulation.steps(), 4);
  loop.setBeforeStep([] { return true; });
  loop.start();
  EXPECT_TRUE(loop.isRunning());
  // Its own counters while it runs (the simulation is the physics thread's until stopped).
  for (int n = 0; n < 500 && loop.statistics().steps < 6; ++n)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  loop.stop();
  EXPECT_GE(simulation.steps(), 10);
}

TEST(RealTimeLoop, CountsOnlyItsOwnSimulatedTime) {
  // A simulation that has already run (a scripted approach, a resumed window): the real-time
  // factor is this loop's simulated time over its wall time, so steps x dt / wall.
  Simulation simulation(loadSceneFile(bundledScenePath()));
  for (int n = 0; n < 300; ++n) simulation.step();
  const LoopStatistics statistics = runLoopFor(simulation, std::chrono::milliseconds(200));
  ASSERT_GT(statistics.steps, 0);
  EXPECT_NEAR(statistics.simulated_s,
              static_cast<double>(statistics.steps) * simulation.timeStep_s(), 1e-9);
  EXPECT_LE(statistics.realtimeFactor(), 1.05);
}

/// No contacts, but every `every`-th query takes `delay` of wall time: an occasional slow step.
class SlowEveryNthQuery final : public ContactProvider {
 public:
  SlowEveryNthQuery(int every, std::chrono::microseconds delay) : m_every(every), m_delay(delay) {}
  void findContacts(const Eigen::Matrix3Xd&, const InstrumentPose&, PenaltyContactSet&) override {
    if (++m_calls % m_every == 0) std::this_thread::sleep_for(m_delay);
  }

 private:
  int m_every;
  std::chrono::microseconds m_delay;
  int m_calls = 0;
};

/// A weightless, untouched liver (every step costs the same: one residual check at rest; the
/// bundled scene's steps under gravity vary too much in cost for the catch-up arithmetic below),
/// with an instrument a metre away (the contact query runs only where there is one), and its
/// time step (the loop's budget) set to 1 ms or four free steps, whichever is longer (sanitizer
/// builds are slower): free steps take a quarter of it at most.
SceneDescription sceneWithRoomyBudget() {
  SceneDescription scene =
      loadSceneFile(std::string(TISSUESIM_TEST_DATA_DIR) + "/scenes/minimal.json");
  scene.instrument.emplace();
  scene.instrument->tipStart_m = Eigen::Vector3d(0.0, 1.0, 0.0);
  Simulation timing(scene);
  const auto start = std::chrono::steady_clock::now();
  for (int n = 0; n < 20; ++n) timing.step();
  const double freeStep_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 20;
  scene.timeStep_s = std::max(1e-3, 4.0 * freeStep_s);
  return scene;
}

TEST(RealTimeLoop, AnOccasionalSlowStepIsMadeUp) {
  // Every tenth step takes 2.5 budgets more than its budget; the others (the free liver) take a
  // quarter of it at most. The loop catches up after each slow step, so simulated time keeps to
  // wall time; a loop that let time fall behind at each late step would lose about a fifth.
  const SceneDescription scene = sceneWithRoomyBudget();
  Simulation simulation(scene);
  const auto budget = std::chrono::microseconds(static_cast<long>(scene.timeStep_s * 1e6));
  SlowEveryNthQuery slow(10, 5 * budget / 2);
  simulation.setContactProvider(&slow);
  const LoopStatistics statistics =
      runLoopFor(simulation, std::chrono::duration_cast<std::chrono::milliseconds>(600 * budget));
  EXPECT_GT(statistics.steps, 100);
  EXPECT_GT(statistics.overruns, 10);  // the slow steps, and some of those catching up
  EXPECT_GT(statistics.realtimeFactor(), 0.9);
  EXPECT_LE(statistics.realtimeFactor(), 1.05);
}

TEST(RealTimeLoop, AStallOfTenStepsIsMadeUp) {
  // Every 60th step stalls for ten budgets (what an operating system's scheduler and other
  // processes do to a thread now and then): within kMaxLagSteps the loop makes it up by
  // running the following steps back to back. With a window of four budgets each stall would
  // lose six, a tenth of the time.
  const SceneDescription scene = sceneWithRoomyBudget();
  Simulation simulation(scene);
  const auto budget = std::chrono::microseconds(static_cast<long>(scene.timeStep_s * 1e6));
  SlowEveryNthQuery slow(60, 10 * budget);
  simulation.setContactProvider(&slow);
  const LoopStatistics statistics =
      runLoopFor(simulation, std::chrono::duration_cast<std::chrono::milliseconds>(700 * budget));
  EXPECT_GT(statistics.steps, 300);
  EXPECT_GT(statistics.realtimeFactor(), 0.95);
  EXPECT_LE(statistics.realtimeFactor(), 1.05);
}

TEST(RealTimeLoop, LateStepsAreCountedAndTimeFallsBehind) {
  SceneDescription scene = loadSceneFile(bundledScenePath());
  scene.timeStep_s = 1e-6;  // a microsecond budget: every step is late
  Simulation simulation(scene);
  const LoopStatistics statistics = runLoopFor(simulation, std::chrono::milliseconds(200));
  EXPECT_GT(statistics.steps, 0);
  EXPECT_EQ(statistics.overruns, statistics.steps);
  EXPECT_LT(statistics.realtimeFactor(), 0.1);
}

/// The highest node within 1 cm (horizontally) of where the scene's tool starts: the top of the
/// anterior lobe the trainee works on, away from the bare area the bundled liver is held by.
Eigen::Index highestNodeUnderTheTool(const Simulation& simulation) {
  const Eigen::Matrix3Xd& x = simulation.state().x;
  const Eigen::Vector3d& tool = simulation.scene().instrument->tipStart_m;
  Eigen::Index top = -1;
  for (Eigen::Index node = 0; node < x.cols(); ++node) {
    if (std::hypot(x(0, node) - tool.x(), x(2, node) - tool.z()) > 0.01) continue;
    if (top < 0 || x(1, node) > x(1, top)) top = node;
  }
  return top;
}

TEST(Grasp, LiftsSurfaceNodesAndReleasesThem) {
  Simulation simulation(loadSceneFile(bundledScenePath()));
  const Eigen::Matrix3Xd rest = simulation.state().x;
  const Eigen::Index top = highestNodeUnderTheTool(simulation);
  const Eigen::Vector3d tip = rest.col(top) + Eigen::Vector3d(0, 0.002, 0);
  const Eigen::Vector3d lifted = tip + Eigen::Vector3d(0, 0.01, 0);
  const InstrumentScript script({{0.0, {tip, {0, -1, 0}, true}},
                                 {0.4, {lifted, {0, -1, 0}, true}},
                                 {0.5, {lifted, {0, -1, 0}, false}},
                                 {1.5, {lifted, {0, -1, 0}, false}}});
  simulation.setInstrumentSource(&script);
  const double restHeight = rest(1, top);
  while (simulation.time_s() < 0.45) ASSERT_TRUE(simulation.step().isGood);
  const std::vector<int> held = simulation.heldNodes();
  ASSERT_FALSE(held.empty());
  EXPECT_NE(std::find(held.begin(), held.end(), static_cast<int>(top)), held.end());
  EXPECT_GT(simulation.state().x(1, top) - restHeight, 0.006);  // lifted most of the 10 mm
  while (simulation.time_s() < 1.5) ASSERT_TRUE(simulation.step().isGood);
  EXPECT_TRUE(simulation.heldNodes().empty());
  EXPECT_LT(simulation.state().x(1, top) - restHeight, 0.003);  // released: it springs back
}

TEST(Grasp, TiltingTheToolSwingsTheHeldTissueRoundTheTip) {
  // Grasp at the top, then tilt the shaft 40 degrees about z, the tip staying put: the held
  // nodes follow their offsets turned with the shaft.
  Simulation simulation(loadSceneFile(bundledScenePath()));
  const Eigen::Matrix3Xd rest = simulation.state().x;
  const Eigen::Index top = highestNodeUnderTheTool(simulation);
  const Eigen::Vector3d tip = rest.col(top) + Eigen::Vector3d(0, 0.002, 0);
  const double angle = 40.0 * 3.14159265358979 / 180.0;
  const Eigen::Vector3d down(0, -1, 0);
  const Eigen::Vector3d tilted(std::sin(angle), -std::cos(angle), 0);
  const InstrumentScript script({{0.0, {tip, down, true}},
                                 {0.1, {tip, down, true}},
                                 {0.5, {tip, tilted, true}},
                                 {1.0, {tip, tilted, true}}});
  simulation.setInstrumentSource(&script);
  while (simulation.time_s() < 0.05) ASSERT_TRUE(simulation.step().isGood);
  const std::vector<int> held = simulation.heldNodes();
  ASSERT_FALSE(held.empty());
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // mean offset of the held nodes from the tip
  for (const int node : held) offset += rest.col(node) - tip;
  offset /= static_cast<double>(held.size());
  while (simulation.time_s() < 1.0) ASSERT_TRUE(simulation.step().isGood);
  Eigen::Vector3d now = Eigen::Vector3d::Zero();
  for (const int node : held) now += simulation.state().x.col(node) - tip;
  now /= static_cast<double>(held.size());
  const Eigen::Vector3d turned = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()) * offset;
  // Closer to the turned offset than to the unturned one, and most of the way there.
  EXPECT_LT((now - turned).norm(), 0.5 * (now - offset).norm());
  EXPECT_LT((now - turned).norm(), 0.35 * (turned - offset).norm());
}

TEST(InstrumentScript, InterpolatesAndLoads) {
  const InstrumentScript poke = InstrumentScript::poke({{0, 0, 0.1}, {0, 0, -1}, false}, 0.02, 1.0);
  EXPECT_NEAR(poke.poseAt(0.5).tip_m.z(), 0.09, 1e-12);
  EXPECT_NEAR(poke.poseAt(1.0).tip_m.z(), 0.08, 1e-12);
  EXPECT_NEAR(poke.poseAt(5.0).tip_m.z(), 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(poke.duration_s(), 2.0);
  EXPECT_THROW(InstrumentScript({{1.0, {}}, {1.0, {}}}), std::invalid_argument);
  EXPECT_THROW(InstrumentScript::load("no-such-script.json"), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
