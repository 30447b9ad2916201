// SPDX-License-Identifier: Apache-2.0
#include "app/SoakCommand.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/SecondsSince.h"
#include "app/AssetPaths.h"
#include "app/CommandError.h"
#include "app/OutputFile.h"
#include "app/ProcessMemory.h"
#include "app/SceneSession.h"
#include "sim/RandomSession.h"
#include "sim/Simulation.h"

namespace tissuesim::app {
namespace {

// Under AddressSanitizer freed blocks wait in its quarantine (256 MB by default), so resident
// memory grows with whatever is allocated and freed (event texts, reports): reported there, not
// judged.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kIsMemoryJudged = false;
#else
constexpr bool kIsMemoryJudged = true;
#endif

struct SoakOptions {
  std::string scenePath;
  double duration_s = 600.0;
  std::uint64_t seed = 1;
  double window_s = 10.0;
  std::string reportPath;
};

/// What one window of simulated time showed.
struct Window {
  double endTime_s = 0.0;
  double stepsPerSecond = 0.0;
  double maxKineticEnergy_J = 0.0;
  double maxDisplacement_m = 0.0;  ///< largest node distance from the start state
  double maxToolForce_N = 0.0;
  double residentMemory_mb = 0.0;  ///< at the window's end
};

void runSoak(const SoakOptions& options) {
  if (!(std::isfinite(options.duration_s) && options.duration_s > 0.0 &&
        options.duration_s <= 86400.0))
    throw CommandError("--duration must be a positive number of seconds, at most a day");
  if (!(std::isfinite(options.window_s) && options.window_s > 0.0))
    throw CommandError("--window must be a positive number of seconds");
  if (!options.reportPath.empty()) checkOutputWritable(options.reportPath, "--report");
  SceneSession session(options.scenePath, "", InstrumentDriver::Script);
  session.printAssumptions();
  Simulation* const simulation = &session.simulation();
  try {
    session.useScript(randomSession(*simulation, options.duration_s, options.seed));
  } catch (const std::invalid_argument& error) {
    throw CommandError(options.scenePath + ": " + error.what());
  }

  const Eigen::Matrix3Xd start = simulation->state().x;
  const Eigen::VectorXd& mass = simulation->springMesh().nodeMass_kg;
  const long steps = std::lround(options.duration_s / simulation->timeStep_s());
  const long stepsPerWindow =
      std::max(1L, std::lround(options.window_s / simulation->timeStep_s()));
  std::vector<Window> windows;
  windows.reserve(static_cast<std::size_t>(steps / stepsPerWindow + 1));
  long badSteps = 0;
  long grasps = 0;
  bool wasGrasping = false;
  Window window;
  auto windowStart = std::chrono::steady_clock::now();
  const auto startWall = windowStart;
  for (long n = 1; n <= steps; ++n) {
    const StepOutcome outcome = simulation->step();
    badSteps += outcome.isGood ? 0 : 1;
    const bool isGrasping = simulation->instrumentPose().isGrasping;
    grasps += isGrasping && !wasGrasping ? 1 : 0;
    wasGrasping = isGrasping;
    window.maxToolForce_N = std::max(window.maxToolForce_N, outcome.contact.toolForce_N.norm());
    if (n % 10 == 0 || n % stepsPerWindow == 0) {  // every 10 ms: the state's energy and reach
      const Eigen::Matrix3Xd& x = simulation->state().x;
      const Eigen::Matrix3Xd& v = simulation->state().v;
      window.maxKineticEnergy_J =
          std::max(window.maxKineticEnergy_J,
                   0.5 * (v.colwise().squaredNorm().transpose().array() * mass.array()).sum());
      window.maxDisplacement_m =
          std::max(window.maxDisplacement_m, (x - start).colwise().norm().maxCoeff());
    }
    if (n % stepsPerWindow == 0 || n == steps) {
      const auto now = std::chrono::steady_clock::now();
      const double wall_s = std::chrono::duration<double>(now - windowStart).count();
      const long windowSteps = n % stepsPerWindow == 0 ? stepsPerWindow : n % stepsPerWindow;
      window.endTime_s = simulation->time_s();
      window.stepsPerSecond = wall_s > 0.0 ? static_cast<double>(windowSteps) / wall_s : 0.0;
      window.residentMemory_mb = residentBytes() / 1e6;
      windows.push_back(window);
      std::fprintf(stderr, "\rsoak: %.0f of %.0f s simulated, %.0f steps/s", window.endTime_s,
                   options.duration_s, window.stepsPerSecond);
      window = Window{};
      windowStart = std::chrono::steady_clock::now();
    }
  }
  std::fprintf(stderr, "\n");
  const double wall_s = secondsSince(startWall);

  // Memory: from the end of the first window (everything sized) to the last.
  const double memoryGrowth_mb =
      windows.size() > 1 ? windows.back().residentMemory_mb - windows.front().residentMemory_mb
                         : 0.0;
  double maxEnergy = 0.0, maxDisplacement = 0.0, minRate = 1e300, maxRate = 0.0;
  for (const Window& w : windows) {
    maxEnergy = std::max(maxEnergy, w.maxKineticEnergy_J);
    maxDisplacement = std::max(maxDisplacement, w.maxDisplacement_m);
    minRate = std::min(minRate, w.stepsPerSecond);
    maxRate = std::max(maxRate, w.stepsPerSecond);
  }
  const std::map<std::string, int> eventsByKind = countEventsByKind(simulation->events());
  const auto nonFiniteKind = eventsByKind.find("non-finite");
  const int nonFinite = nonFiniteKind == eventsByKind.end() ? 0 : nonFiniteKind->second;
  const std::string eventSummary = eventKindSummary(simulation->events());

  nlohmann::json report;
  report["scene"] = options.scenePath;
  report["seed"] = options.seed;
  report["simulated_seconds"] = simulation->time_s();
  report["wall_seconds"] = wall_s;
  report["steps"] = simulation->steps();
  report["failed_steps"] = badSteps;
  report["grasps"] = grasps;
  report["instability_event_count"] = simulation->eventCount();
  report["non_finite_events"] = nonFinite;
  report["events_by_kind"] = eventsByKind;  // of the first events().size()
  report["instability_events_kept"] = simulation->events().size();
  report["max_kinetic_energy_j"] = maxEnergy;
  report["max_displacement_mm"] = maxDisplacement * 1e3;
  report["memory_growth_mb"] = memoryGrowth_mb;
  report["memory_judged"] = kIsMemoryJudged;
  report["windows"] = nlohmann::json::array();
  for (const Window& w : windows) {
    report["windows"].push_back({{"end_s", w.endTime_s},
                                 {"steps_per_s", w.stepsPerSecond},
                                 {"max_kinetic_energy_j", w.maxKineticEnergy_J},
                                 {"max_displacement_mm", w.maxDisplacement_m * 1e3},
                                 {"max_tool_force_n", w.maxToolForce_N},
                                 {"resident_memory_mb", w.residentMemory_mb}});
  }
  if (!options.reportPath.empty())
    writeTextFile(options.reportPath, "--report", report.dump(2) + "\n");
  std::printf(
      "soak of %s: %.0f s simulated in %.0f s, %ld steps, %ld grasps; %ld failed steps, %zu "
      "instability events (of the first %zu: %s); kinetic energy at most %.3g J, nodes at most "
      "%.1f "
      "mm from the start, memory %+.2f MB after the first %.0f s; %.0f-%.0f steps/s\n",
      options.scenePath.c_str(), simulation->time_s(), wall_s, simulation->steps(), grasps,
      badSteps, simulation->eventCount(), simulation->events().size(),
      eventSummary.empty() ? "none" : eventSummary.c_str(), maxEnergy, maxDisplacement * 1e3,
      memoryGrowth_mb, options.window_s, minRate, maxRate);
  // What a long session must never show. Bounds: a liver moving as a whole at 1 m/s has about
  // 0.6 J; a node 20 cm from where it started has left any organ; memory is sized by the end of
  // the first window, so a few MB more is a leak.
  if (nonFinite > 0 || badSteps > 0)
    throw CommandError("the soak saw " + std::to_string(badSteps) + " failed steps (" +
                       std::to_string(nonFinite) + " non-finite)");
  if (!(maxEnergy < 1.0) || !(maxDisplacement < 0.2))
    throw CommandError("the soak's energy or reach grew without bound (kinetic energy " +
                       std::to_string(maxEnergy) + " J, a node " +
                       std::to_string(maxDisplacement * 1e3) + " mm from the start)");
  if (kIsMemoryJudged && memoryGrowth_mb > 5.0)
    throw CommandError("the soak's memory grew by " + std::to_string(memoryGrowth_mb) +
                       " MB after its first window");
}

}  // namespace

void registerSoakCommand(CLI::App& app) {
  auto options = std::make_shared<SoakOptions>();
  CLI::App* command = app.add_subcommand(
      "soak",
      "A long headless session of random pokes (up to 5 cm deep, 2 cm/s to 1.5 m/s), grasps and "
      "releases, reproducible from its seed: fails on a non-finite or failed step, unbounded "
      "energy or growing memory; reports the physics rate over time.");
  options->scenePath = bundledAsset("scenes/liver-poke.json").string();
  command->add_option("--scene", options->scenePath, "Scene file (JSON)")->capture_default_str();
  command->add_option("--duration", options->duration_s, "Simulated seconds")
      ->capture_default_str();
  command->add_option("--seed", options->seed, "Seed of the random session")->capture_default_str();
  command
      ->add_option("--window", options->window_s,
                   "Simulated seconds per reported window (rate, energy, memory)")
      ->capture_default_str();
  command->add_option("--report", options->reportPath, "Write the JSON report here");
  command->callback([options] { runSoak(*options); });
}

}  // namespace tissuesim::app
