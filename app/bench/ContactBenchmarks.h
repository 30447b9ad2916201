#pragma once
// Benchmarks of collision on the bundled liver scene: the contact query and response alone
// (refit, FCL collide, penalty), and a whole physics step with the probe pressed in, against the
// 1 ms budget of a 1 kHz haptic loop.

#include <string>

#include "sim/Simulation.h"

namespace tissuesim::app {

/// The scene's probe pressed 5 mm into the liver's highest point (the contact and rendering
/// benchmarks' fixed load).
InstrumentPose pressedPose(const Simulation& simulation);

void registerContactBenchmarks(const std::string& scenePath);

}  // namespace tissuesim::app
