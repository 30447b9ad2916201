// SPDX-License-Identifier: Apache-2.0
#pragma once
// A scene ready to step: the Simulation, FCL contact for its instrument, and where the
// instrument's pose comes from (a script, or live from the GUI). Shared by `run`, `snapshot`
// and the window, so all three build a scene the same way.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "collision/CapsuleContact.h"
#include "sim/InstrumentScript.h"
#include "sim/RealTimeLoop.h"
#include "sim/Simulation.h"

namespace tissuesim::app {

enum class InstrumentDriver { Script, Live };

/// The scene file read and checked. @throws CommandError with the file's one-line reason.
SceneDescription readScene(const std::string& scenePath);

class SceneSession {
 public:
  /// Loads the scene. With a Script driver an empty scriptPath means the default poke
  /// (4 cm along the tool over 1 s). @throws CommandError with the file's one-line reason.
  SceneSession(const std::string& scenePath, const std::string& scriptPath,
               InstrumentDriver driver);
  /// The same from a scene already read (and perhaps changed: `trade` varies its knobs).
  SceneSession(const SceneDescription& scene, const std::string& scriptPath,
               InstrumentDriver driver);

  Simulation& simulation() { return *m_simulation; }
  const Simulation& simulation() const { return *m_simulation; }
  const SceneDescription& scene() const { return m_simulation->scene(); }
  /// What loading assumed (a mesh file's guessed unit), one line each: for the user to see.
  const std::vector<std::string>& assumptions() const {
    return m_simulation->geometry().assumptions;
  }
  /// Prints assumptions() on stdout (a command's report stream: stderr carries a failure's one
  /// line alone).
  void printAssumptions() const;
  /// The script (null: no instrument, or driven live).
  const InstrumentScript* script() const { return m_script.get(); }
  /// The live pose the GUI writes (null: no instrument, or scripted).
  LiveInstrument* liveInstrument() { return m_live.get(); }
  /// The simulation's tissue replaced (Simulation::replaceTissue), and the live tool's speed
  /// limit with it where the scene's model sets one from the tissue (fem-haptic-rate:
  /// sim/HapticRateReach.h). From the stepping thread, or while no step runs.
  void replaceTissue(const TissueParameters& parameters);
  /// The body made again where the tool aims (Simulation::refineTowardsTool), the instrument's
  /// contact with it rebuilt for the new mesh. From the stepping thread, or while no step runs.
  /// @returns whether it was made again. @throws CommandError with the scene's one-line reason.
  bool refineTowardsTool();
  /// Drives the instrument by `script` from now on (one built from the simulation, as the
  /// soak's random session is). The scene must have an instrument.
  void useScript(InstrumentScript script);

 private:
  std::optional<Simulation> m_simulation;
  std::unique_ptr<InstrumentScript> m_script;
  std::unique_ptr<LiveInstrument> m_live;
  std::unique_ptr<CapsuleContact> m_contact;
};

}  // namespace tissuesim::app
