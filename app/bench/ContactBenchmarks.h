// SPDX-License-Identifier: Apache-2.0
#pragma once
// Benchmarks of collision on the bundled liver scene: the contact query and response alone
// (refit, FCL collide, penalty), and a whole physics step with the probe held pressed in,
// against the 1 ms budget of a 1 kHz haptic loop.

#include <string>

#include "sim/RealTimeLoop.h"
#include "sim/SceneFile.h"
#include "sim/Simulation.h"

namespace tissuesim::app {

/// The load a held probe is timed under (the contact and rendering benchmarks'): the bundled
/// poke's deepest pose, the scene's probe 4 cm down from its start, reached in 1 s with the
/// simulation stepped along the way through `live` (which the simulation must be reading).
/// Returns that pose; the liver is then pressed in at about 1.9 N. (A probe put 5 mm into the
/// liver's crest at once, the earlier load, slipped off it within a second and left a few
/// millinewtons of contact, so it timed an almost free liver.)
InstrumentPose pressToPokeDepth(Simulation& simulation, const SceneDescription& scene,
                                LiveInstrument& live);

void registerContactBenchmarks(const std::string& scenePath);

}  // namespace tissuesim::app
