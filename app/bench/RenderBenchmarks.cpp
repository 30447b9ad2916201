// SPDX-License-Identifier: Apache-2.0
#include "app/bench/RenderBenchmarks.h"

#include <chrono>
#include <memory>
#include <thread>

#include <benchmark/benchmark.h>

#include "app/HeadlessDisplay.h"
#include "app/SceneSession.h"
#include "app/bench/ContactBenchmarks.h"
#include "render/OffscreenImage.h"
#include "render/TissueSceneView.h"

namespace tissuesim::app {
namespace {

/// Started on the first render benchmark only: a filtered run without them starts no Xvfb.
void ensureDisplay() {
  leaveACoreForPhysics();  // as the window does: frames and physics rates are the window's
  static std::unique_ptr<HeadlessDisplay> display;
  if (!display) display = std::make_unique<HeadlessDisplay>(true);
}

void frameBenchmark(benchmark::State& state, const std::string& scenePath, bool isColourMap) {
  ensureDisplay();
  SceneSession session(scenePath, "", InstrumentDriver::Script);
  Simulation& simulation = session.simulation();
  for (int n = 0; n < 600; ++n) simulation.step();  // mid-poke: a deformed surface
  TissueSceneView view(simulation.geometry(), simulation.springMesh(), &*session.scene().instrument,
                       session.scene().tray ? &*session.scene().tray : nullptr);
  view.setColourMap(isColourMap);
  OffscreenWindow window(view.renderer(), 1280, 800);
  for (auto _ : state) {
    // What the window does per frame: move the surface to the snapshot and draw it.
    view.update(simulation.state().x, simulation.instrumentPose());
    window.render();
  }
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["springs"] = static_cast<double>(simulation.springMesh().springCount());
}

/// The real-time loop for 3 s of wall time with the probe held at the poke's depth, alone or with
/// the main thread rendering frames at up to 60 per second as the window does.
void physicsRateBenchmark(benchmark::State& state, const std::string& scenePath, bool isRendering) {
  if (isRendering) ensureDisplay();
  SceneSession session(scenePath, "", InstrumentDriver::Live);
  Simulation& simulation = session.simulation();
  pressToPokeDepth(simulation, session.scene(), *session.liveInstrument());
  std::unique_ptr<TissueSceneView> view;
  std::unique_ptr<OffscreenWindow> window;
  if (isRendering) {
    view = std::make_unique<TissueSceneView>(
        simulation.geometry(), simulation.springMesh(), &*session.scene().instrument,
        session.scene().tray ? &*session.scene().tray : nullptr);
    window = std::make_unique<OffscreenWindow>(view->renderer(), 1280, 800);
  }
  long frames = 0;
  LoopStatistics statistics;
  for (auto _ : state) {
    RealTimeLoop loop(simulation);
    loop.start();
    const auto start = std::chrono::steady_clock::now();
    auto next = start;
    while (std::chrono::steady_clock::now() - start < std::chrono::seconds(3)) {
      if (isRendering) {
        const SimulationSnapshot& snapshot = loop.snapshot();
        view->update(snapshot.positions_m, snapshot.instrument);
        window->render();
        ++frames;
        next += std::chrono::microseconds(16667);
        std::this_thread::sleep_until(next);
      } else {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    }
    state.counters["tool_force_n"] = loop.snapshot().toolForce_N.norm();
    loop.stop();
    statistics = loop.statistics();
  }
  state.counters["physics_hz"] = statistics.physicsHz();
  state.counters["realtime_factor"] = statistics.realtimeFactor();
  state.counters["overruns"] = static_cast<double>(statistics.overruns);
  state.counters["fps"] = static_cast<double>(frames) / 3.0;
}

}  // namespace

void registerRenderBenchmarks(const std::string& scenePath) {
  benchmark::RegisterBenchmark(
      "Render/Frame/liver/1280x800",
      [scenePath](benchmark::State& state) { frameBenchmark(state, scenePath, false); })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  benchmark::RegisterBenchmark(
      "Render/Frame/liver/1280x800/colour_map",
      [scenePath](benchmark::State& state) { frameBenchmark(state, scenePath, true); })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  for (const bool isRendering : {false, true}) {
    benchmark::RegisterBenchmark(
        isRendering ? "Render/PhysicsRate/with_rendering" : "Render/PhysicsRate/alone",
        [scenePath, isRendering](benchmark::State& state) {
          physicsRateBenchmark(state, scenePath, isRendering);
        })
        ->Iterations(1)
        ->Unit(benchmark::kMillisecond);
  }
}

}  // namespace tissuesim::app
