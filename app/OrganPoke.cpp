// SPDX-License-Identifier: Apache-2.0
#include "app/OrganPoke.h"

#include <chrono>
#include <cmath>

#include "app/CommandError.h"
#include "app/FemForceCache.h"
#include "app/SceneSession.h"
#include "mesh/TetMeshFile.h"
#include "mesh/TriangleSurface.h"
#include "sim/HapticRateBody.h"
#include "sim/SessionRecording.h"

namespace tissuesim::app {
namespace {

/// Where the simulator's probe starts: this far above the point where its axis meets the
/// surface (m).
constexpr double kApproach_m = 0.001;

/// The checks both kinds of poke make.
void checkPokeScene(const SceneDescription& scene) {
  if (!scene.instrument)
    throw CommandError("the scene " + scene.source.string() + " has no instrument to poke with");
  if (!scene.fixed.box_m) {
    throw CommandError("the scene " + scene.source.string() +
                       " holds listed nodes; the organ poke needs its fixed region as a box");
  }
}

}  // namespace

TetMesh readOrganMesh(const std::string& path) {
  try {
    return readTetMesh(path);
  } catch (const MeshFileError& error) {
    throw CommandError(error.what());
  }
}

SceneDescription weightlessPokeScene(SceneDescription scene) {
  checkPokeScene(scene);
  scene.gravity_m_s2.setZero();
  scene.tray.reset();
  return scene;
}

SceneDescription weightedPokeScene(SceneDescription scene) {
  checkPokeScene(scene);
  if (!(scene.gravity_m_s2.squaredNorm() > 0.0))
    throw CommandError("the scene " + scene.source.string() +
                       " has no gravity to poke the organ under");
  if (scene.tray && scene.tray->friction > 0.0)
    throw CommandError("the scene " + scene.source.string() +
                       " has friction on its tray; the reference's tray is frictionless");
  return scene;
}

OrganPokeSetup organPokeSetup(const SceneDescription& scene, const std::vector<double>& depths_m,
                              double density_kg_m3) {
  OrganPokeSetup setup;
  setup.tipStart_m = scene.instrument->tipStart_m;
  setup.direction = scene.instrument->direction;
  setup.probeRadius_m = scene.instrument->shaftRadius_m;
  setup.fixedBox_m = *scene.fixed.box_m;
  setup.depths_m = depths_m;
  setup.gravity_m_s2 = scene.gravity_m_s2;
  setup.density_kg_m3 = density_kg_m3;
  if (scene.tray) {
    setup.tray =
        OrganPokeSetup::Tray{scene.tray->up, scene.tray->height_m, scene.tray->stiffness_Pa_per_m};
  }
  return setup;
}

std::uint64_t femReferenceKey(const SceneDescription& scene, const std::string& femMeshPath,
                              const OrganPokeSetup& setup, double bulkModulus_Pa) {
  FemReferenceKey key;
  try {
    key.addText(std::to_string(fileHash(scene.tissue)));
    key.addText(std::to_string(fileHash(femMeshPath)));
  } catch (const RecordingError& error) {
    throw CommandError(error.what());
  }
  for (const Eigen::Vector3d& v :
       {setup.tipStart_m, setup.direction, setup.fixedBox_m.min(), setup.fixedBox_m.max()})
    for (int i = 0; i < 3; ++i) key.addNumber(v[i]);
  for (const double value : {setup.probeRadius_m, setup.depthStep_m, setup.pressureStiffness_Pa_m,
                             setup.contactReach_m, bulkModulus_Pa})
    key.addNumber(value);
  // The node contact's keys (every kept reference's) stay as they were.
  if (setup.contactSpacing_m > 0.0) key.addNumber(setup.contactSpacing_m);
  // So are the weightless ones'.
  if (setup.gravity_m_s2.squaredNorm() > 0.0) {
    key.addText("weighted");
    for (int i = 0; i < 3; ++i) key.addNumber(setup.gravity_m_s2[i]);
    key.addNumber(setup.density_kg_m3);
    if (setup.tray) {
      for (int i = 0; i < 3; ++i) key.addNumber(setup.tray->up[i]);
      key.addNumber(setup.tray->height_m);
      key.addNumber(setup.tray->stiffness_Pa_per_m);
    }
  }
  return key.value();
}

SimulatorPoke pokeSimulator(const SceneDescription& scene, const std::vector<double>& depths_m,
                            double speed_m_s) {
  const auto start = std::chrono::steady_clock::now();
  SceneSession session(scene, "", InstrumentDriver::Script);
  Simulation& simulation = session.simulation();
  const SceneInstrument& tool = *scene.instrument;
  Eigen::Vector3d entry;
  // Under gravity on the surface as the organ opened settled; weightless, the drawn surface as
  // read (the same place, without the embedding's round-off).
  const bool isFound =
      scene.gravity_m_s2.squaredNorm() > 0.0
          ? firstOrganCrossing(simulation.geometry(), simulation.state().x, tool.tipStart_m,
                               tool.direction, entry)
          : firstOrganCrossing(simulation.geometry(), tool.tipStart_m, tool.direction, entry);
  if (!isFound) {
    throw CommandError("the instrument's axis in " + scene.source.string() +
                       " does not meet the organ's surface");
  }
  const double travel_m = kApproach_m + depths_m.back() + simulation.timeStep_s() * speed_m_s;
  session.useScript(InstrumentScript::poke(
      InstrumentPose{entry - kApproach_m * tool.direction, tool.direction, false}, travel_m,
      travel_m / speed_m_s));
  SimulatorPoke poke;
  double lastDepth = -kApproach_m, lastForce = 0.0;
  // A refused step leaves the time, and so the probe, where it was: count attempts, not steps.
  const long attemptLimit =
      2 * static_cast<long>(std::ceil(travel_m / speed_m_s / simulation.timeStep_s()));
  const HapticRateBody* body = simulation.hapticRateBody();
  poke.nodes = body != nullptr ? static_cast<int>(body->nodeCount())
                               : static_cast<int>(simulation.springMesh().nodeCount());
  double waiting_s = 0.0;
  poke.stepTimes_ms.reserve(static_cast<std::size_t>(attemptLimit) + 2);
  const auto stepping = std::chrono::steady_clock::now();
  for (long attempt = 0; poke.force_N.size() < depths_m.size(); ++attempt) {
    if (attempt > attemptLimit) {
      throw CommandError("the simulator of " + scene.source.string() + " did not reach " +
                         std::to_string(1e3 * depths_m[poke.force_N.size()]) + " mm (" +
                         std::to_string(simulation.eventCount()) + " instability events)");
    }
    const auto before = std::chrono::steady_clock::now();
    const StepOutcome outcome = simulation.step();
    const double waited_s = body != nullptr ? body->lastWait_s() : 0.0;
    waiting_s += waited_s;
    poke.stepTimes_ms.push_back(
        1e3 * (std::chrono::duration<double>(std::chrono::steady_clock::now() - before).count() -
               waited_s));
    ++poke.steps;
    const double depth = (simulation.instrumentPose().tip_m - entry).dot(tool.direction);
    const double force = -outcome.contact.toolForce_N.dot(tool.direction);
    while (poke.force_N.size() < depths_m.size() && depth >= depths_m[poke.force_N.size()]) {
      const double target = depths_m[poke.force_N.size()];
      poke.force_N.push_back(lastForce +
                             (force - lastForce) * (target - lastDepth) / (depth - lastDepth));
    }
    lastDepth = depth;
    lastForce = force;
  }
  const auto end = std::chrono::steady_clock::now();
  poke.stepping_s = std::chrono::duration<double>(end - stepping).count() - waiting_s;
  poke.events = static_cast<long>(simulation.eventCount());
  poke.eventKinds = eventKindSummary(simulation.events());
  if (body != nullptr) {
    poke.updates = body->updatesTaken();
    poke.updateMean_ms = poke.updates > 0 ? 1e3 * body->updating_s() / poke.updates : 0.0;
  }
  poke.seconds = std::chrono::duration<double>(end - start).count();
  return poke;
}

}  // namespace tissuesim::app
