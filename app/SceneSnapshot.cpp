// SPDX-License-Identifier: Apache-2.0
#include "app/SceneSnapshot.h"

#include <algorithm>
#include <cmath>

#include "render/OffscreenImage.h"
#include "render/TissueSceneView.h"

namespace tissuesim::app {

SceneSnapshot takeSceneSnapshot(SceneSession& session, const SnapshotSettings& settings) {
  Simulation& simulation = session.simulation();
  SceneSnapshot snapshot;
  const long steps = std::lround(settings.frames / kSnapshotFrameRate_Hz / simulation.timeStep_s());
  for (long n = 0; n < steps; ++n) {
    const StepOutcome outcome = simulation.step();
    snapshot.maxToolForce_N = std::max(snapshot.maxToolForce_N, outcome.contact.toolForce_N.norm());
    snapshot.badSteps += outcome.isGood ? 0 : 1;
  }
  const auto& instrument = session.scene().instrument;
  TissueSceneView view(simulation.geometry(), simulation.springMesh(),
                       instrument ? &*instrument : nullptr,
                       simulation.scene().tray ? &*simulation.scene().tray : nullptr);
  view.setColourMap(settings.isColourMap);
  view.setWireframe(settings.isWireframe);
  view.update(simulation.state().x, simulation.instrumentPose());
  snapshot.image = renderOffscreen(view.renderer(), settings.size.width, settings.size.height);
  return snapshot;
}

}  // namespace tissuesim::app
