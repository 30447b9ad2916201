// SPDX-License-Identifier: Apache-2.0
#include "app/SessionSteps.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "analysis/SecondsSince.h"
#include "app/AssessmentReport.h"
#include "app/CommandError.h"
#include "app/ElasticModelWords.h"
#include "app/OutputFile.h"
#include "render/TimeSeriesExport.h"
#include "sim/SceneFile.h"
#include "sim/Simulation.h"

namespace tissuesim::app {

void applyRecordedChanges(const SessionRecording& recording, std::size_t& next, long step,
                          SceneSession& session) {
  Simulation& simulation = session.simulation();
  for (; next < recording.events.size() && recording.events[next].step <= step; ++next) {
    const RecordedEvent& event = recording.events[next];
    if (event.isReset) simulation.reset();
    if (event.softening) simulation.setSoftening(*event.softening);
    if (event.gravity_m_s2) simulation.setGravity(*event.gravity_m_s2);
    if (event.tissue) session.replaceTissue(*event.tissue);
    if (event.isRefinedTowardsTool) session.refineTowardsTool();
    if (event.pose && session.liveInstrument() != nullptr)
      session.liveInstrument()->setPose(*event.pose);
  }
}

void runSessionSteps(SceneSession& session, long steps, const SessionOutputs& outputs) {
  Simulation* simulation = &session.simulation();
  const SceneDescription& scene = simulation->scene();
  if (!outputs.exportFolder.empty() &&
      !(std::isfinite(outputs.exportEvery_s) && outputs.exportEvery_s > 0.0)) {
    throw CommandError("--export-every must be a positive number of seconds");
  }
  // The export's writing is timed apart: the physics rate reported is the physics' alone.
  std::optional<TimeSeriesExport> exporter;
  double exportWall_s = 0.0;
  double nextExport_s = 0.0;
  const auto exportFrame = [&] {
    const auto begin = std::chrono::steady_clock::now();
    try {
      exporter->write(simulation->time_s(), simulation->state().x);
    } catch (const std::runtime_error& error) {
      throw CommandError(std::string("--export: ") + error.what());
    }
    exportWall_s += secondsSince(begin);
    nextExport_s = simulation->time_s() + outputs.exportEvery_s - 0.5 * simulation->timeStep_s();
  };
  if (!outputs.exportFolder.empty()) {
    try {
      exporter.emplace(outputs.exportFolder, simulation->geometry(), simulation->springMesh());
    } catch (const std::runtime_error& error) {
      throw CommandError(std::string("--export: ") + error.what());
    }
    exportFrame();
  }

  double maxForce = 0.0;
  double maxPenetration = 0.0;
  double maxStretch = 1.0;
  double minVolumeRatio = 1.0;
  double maxVolumeRatio = 1.0;
  long linearIterations = 0;
  long newtonIterations = 0;
  long badSteps = 0;
  const auto start = std::chrono::steady_clock::now();
  for (long n = 0; n < steps; ++n) {
    if (outputs.beforeStep) outputs.beforeStep(n);
    const StepOutcome outcome = simulation->step();
    maxForce = std::max(maxForce, outcome.contact.toolForce_N.norm());
    maxPenetration = std::max(maxPenetration, outcome.contact.maxPenetration_m);
    // A step that was rolled back left no state behind: its stretch is not the organ's.
    if (outcome.isGood) maxStretch = std::max(maxStretch, outcome.maxStretch);
    minVolumeRatio = std::min(minVolumeRatio, outcome.integrator.forces.volume.minVolumeRatio);
    maxVolumeRatio = std::max(maxVolumeRatio, outcome.integrator.forces.volume.maxVolumeRatio);
    linearIterations += outcome.integrator.linearIterations;
    newtonIterations += outcome.integrator.iterations;
    badSteps += outcome.isGood ? 0 : 1;
    if (exporter && simulation->time_s() >= nextExport_s) exportFrame();
    if (outputs.afterStep) outputs.afterStep(n);
  }
  const double wall = secondsSince(start) - exportWall_s;

  nlohmann::json report;
  report["scene"] = outputs.sceneLabel;
  report["steps"] = simulation->steps();
  report["refused_or_failed_steps"] = badSteps;
  report["time_step_s"] = simulation->timeStep_s();
  report["simulated_seconds"] = simulation->time_s();
  report["physics_hz"] = wall > 0.0 ? static_cast<double>(steps) / wall : 0.0;
  report["realtime_factor"] = wall > 0.0 ? simulation->time_s() / wall : 0.0;
  report["max_tool_force_n"] = maxForce;
  report["max_penetration_mm"] = maxPenetration * 1e3;
  report["max_stretch"] = maxStretch;
  if (simulation->bulkModulus() > 0.0) {
    // The volume term's kappa and the range of tet volume ratios J = V / V0 it allowed.
    report["volume_term_kpa"] = simulation->bulkModulus() / 1000.0;
    report["volume_cells"] = scene.volumeCells;
    report["min_volume_ratio"] = minVolumeRatio;
    report["max_volume_ratio"] = maxVolumeRatio;
  }
  report["cg_products_per_step"] =
      steps > 0 ? static_cast<double>(linearIterations) / static_cast<double>(steps) : 0.0;
  // The real-time integrator's extra iterations included (taken where a step's residual stays
  // above an event's): where a stiff or finely meshed scene's steps spend their time.
  report["newton_iterations_per_step"] =
      steps > 0 ? static_cast<double>(newtonIterations) / static_cast<double>(steps) : 0.0;
  report["model"] = scene.model;
  if (scene.model == "fem") report["strain_cells"] = scene.strainCells;
  report["springs"] = simulation->springMesh().springCount();
  report["tets"] = simulation->geometry().mesh.tetCount();
  report["nodes"] = simulation->springMesh().nodeCount();
  // The body made again where the tool aims (Simulation::refineTowardsTool), where it can be.
  if (simulation->refinementCentre()) report["refined_towards_tool"] = simulation->refinements();
  report["integrator"] = scene.integrator;
  report["instability_event_count"] = simulation->eventCount();  // the list keeps the first 100
  report["instability_events"] = nlohmann::json::array();
  for (const InstabilityEvent& event : simulation->events()) {
    report["instability_events"].push_back({{"step", event.step},
                                            {"time_s", event.time_s},
                                            {"kind", event.kind},
                                            {"detail", event.detail}});
  }
  report["assessment"] = assessmentJson(simulation->assessment().summary());
  report["wall_seconds"] = wall;
  if (exporter) {
    report["export"] = {{"collection", exporter->collectionPath().string()},
                        {"frames", exporter->frameCount()},
                        {"wall_seconds", exportWall_s}};
  }
  const bool isFem = scene.model != "springs";
  std::printf(
      "%s: %ld steps of %.3g ms, %.0f Hz (real-time factor %.2f), %ld %s; max tool force "
      "%.3f N, max penetration %.2f mm, max stretch %.3f; %zu instability events\n",
      scene.name.c_str(), simulation->steps(), simulation->timeStep_s() * 1e3,
      report["physics_hz"].get<double>(), report["realtime_factor"].get<double>(),
      static_cast<long>(isFem ? simulation->geometry().mesh.tetCount()
                              : simulation->springMesh().springCount()),
      elasticModelWords(scene).c_str(), maxForce, maxPenetration * 1e3, maxStretch,
      simulation->eventCount());
  if (exporter) {
    std::printf("exported %d frames: %s\n", exporter->frameCount(),
                exporter->collectionPath().string().c_str());
  }
  if (!outputs.reportPath.empty())
    writeTextFile(outputs.reportPath, "--report", report.dump(2) + "\n");
}

}  // namespace tissuesim::app
