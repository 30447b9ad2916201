// SPDX-License-Identifier: Apache-2.0
#pragma once
// How fast the probe may move in a scene whose model is fem-haptic-rate (sim/HapticRateBody.h):
// between two FEM updates the body answers the probe linearly, about where the last update left
// it, and that holds while the probe travels a fraction of a millimetre between updates (the
// staggered iteration's reach, measured on the liver poke: docs/performance-details.md, "The
// probe's contact sampled on the quadratic surface"). The window's tool and the default poke
// move no faster than that reach per update.

#include "sim/SceneFile.h"

namespace tissuesim {

/// The probe's travel between updates that the scheme holds within 10 % of the reference (m).
inline constexpr double kHapticRateReach_m = 0.0006;
/// The time an update takes where the scene uses each one when it is done (latency 0): about
/// what one takes on one core of a desktop machine for the bundled body (s).
inline constexpr double kHapticRateUpdateGuess_s = 0.1;

/// The default poke's travel along the tool in such a scene (m): from the bundled scene's start,
/// about 7 mm into the liver, where the continuum reference still has its equilibrium.
inline constexpr double kHapticRateDefaultPokeDepth_m = 0.015;

/// The probe's speed limit for the scene (m/s): its reach per update.
inline double hapticRateToolSpeed_m_s(const SceneDescription& scene) {
  return kHapticRateReach_m /
         (scene.femUpdateLatency_s > 0.0 ? scene.femUpdateLatency_s : kHapticRateUpdateGuess_s);
}

}  // namespace tissuesim
