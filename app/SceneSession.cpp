// SPDX-License-Identifier: Apache-2.0
#include "app/SceneSession.h"

#include <cstdio>
#include <stdexcept>
#include <utility>

#include "app/CommandError.h"
#include "material/TissueFile.h"
#include "mesh/TetMesh.h"
#include "mesh/TriangleSurface.h"
#include "sim/HapticRateReach.h"
#include "sim/SceneFile.h"

namespace tissuesim::app {

SceneDescription readScene(const std::string& scenePath) {
  try {
    return loadSceneFile(scenePath);
  } catch (const SceneFileError& error) {
    throw CommandError(error.what());
  }
}

SceneSession::SceneSession(const std::string& scenePath, const std::string& scriptPath,
                           InstrumentDriver driver)
    : SceneSession(readScene(scenePath), scriptPath, driver) {}

SceneSession::SceneSession(const SceneDescription& scene, const std::string& scriptPath,
                           InstrumentDriver driver) {
  try {
    m_simulation.emplace(scene);
  } catch (const SceneFileError& error) {
    throw CommandError(error.what());
  } catch (const TissueFileError& error) {
    throw CommandError(error.what());
  }
  const SceneDescription& description = m_simulation->scene();
  if (!description.instrument) {
    if (!scriptPath.empty()) {
      throw CommandError("--script given, but the scene " + description.source.string() +
                         " has no instrument");
    }
    return;
  }
  const InstrumentPose start{description.instrument->tipStart_m, description.instrument->direction,
                             false};
  // The FEM at its own rate follows the probe only so fast (sim/HapticRateReach.h): its tool
  // moves no faster near the organ, and its default poke goes at that speed.
  const bool isHapticRate = description.model == "fem-haptic-rate";
  ToolMotionLimits limits;
  double pokeDepth_m = kDefaultPokeDepth_m, pokeTime_s = kDefaultPokePressTime_s;
  if (isHapticRate) {
    limits = hapticRateToolLimits(description, m_simulation->energy());
    // 7 mm past where the tool's axis meets the organ as it opens: a liver settled under its
    // weight lies further below the scene's start than the weightless one.
    Eigen::Vector3d entry;
    pokeDepth_m =
        firstCrossing(m_simulation->startState().x, boundaryFaces(m_simulation->geometry().mesh),
                      start.tip_m, start.direction, entry)
            ? (entry - start.tip_m).dot(start.direction) + kHapticRateDefaultPokeIntoOrgan_m
            : kHapticRateDefaultPokeDepth_m;
    pokeTime_s = pokeDepth_m / limits.nearSpeed_m_s;
  }
  if (driver == InstrumentDriver::Live) {
    // The window's tool follows the mouse as a proxy (bounded speed and acceleration), so a
    // cursor jump never drives it through the tissue.
    m_live = std::make_unique<LiveInstrument>(start, limits);
    m_simulation->setInstrumentSource(m_live.get());
  } else {
    try {
      m_script = scriptPath.empty()
                     ? std::make_unique<InstrumentScript>(InstrumentScript::poke(
                           {description.instrument->tipStart_m, description.instrument->direction},
                           pokeDepth_m, pokeTime_s))
                     : std::make_unique<InstrumentScript>(InstrumentScript::load(scriptPath));
    } catch (const std::invalid_argument& error) {
      throw CommandError(error.what());
    }
    m_simulation->setInstrumentSource(m_script.get());
  }
  m_contact = makeInstrumentContact(*m_simulation);
  m_simulation->setContactProvider(m_contact.get());
}

void SceneSession::replaceTissue(const TissueParameters& parameters) {
  m_simulation->replaceTissue(parameters);
  // The reach per update depends on the tissue (its stiffest tangent sets the reference's bulk
  // modulus, against which the scene's is judged).
  const SceneDescription& scene = m_simulation->scene();
  if (m_live && scene.model == "fem-haptic-rate")
    m_live->setNearSpeed(hapticRateToolSpeed_m_s(scene, m_simulation->energy()));
}

bool SceneSession::refineTowardsTool() {
  try {
    if (!m_simulation->refineTowardsTool()) return false;
  } catch (const SceneFileError& error) {
    throw CommandError(error.what());
  }
  m_contact = makeInstrumentContact(*m_simulation);
  m_simulation->setContactProvider(m_contact.get());
  return true;
}

void SceneSession::printAssumptions() const {
  for (const std::string& line : assumptions()) std::printf("%s\n", line.c_str());
}

void SceneSession::useScript(InstrumentScript script) {
  m_script = std::make_unique<InstrumentScript>(std::move(script));
  m_simulation->setInstrumentSource(m_script.get());
}

}  // namespace tissuesim::app
