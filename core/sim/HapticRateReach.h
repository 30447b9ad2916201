// SPDX-License-Identifier: Apache-2.0
#pragma once
// How fast the probe may move in a scene whose model is fem-haptic-rate (sim/HapticRateBody.h):
// between two FEM updates the body answers the probe linearly, about where the last update left
// it, and that holds while the probe travels a fraction of a millimetre between updates (the
// staggered iteration's reach, measured on the liver poke: docs/performance-details.md, "One
// Newton iteration an update on a softer volume term"). The default poke moves no faster than
// that reach per update, nor does the window's tool near the organ; in free space the tool
// moves at its own limit and brakes to that speed before it comes near (sim/ToolProxy.h).

#include "material/StrainEnergy.h"
#include "sim/SceneFile.h"
#include "sim/ToolProxy.h"

namespace tissuesim {

/// The probe's travel between updates that the scheme holds within 10 % of the reference (m),
/// for an update's Newton iterations, its body's bulk modulus and whether it hangs under its
/// weight: two iterations, or one on a weightless body whose bulk modulus is at most a tenth of
/// the reference's (defaultFemBulkModulus), hold 0.36 mm wherever the first touch falls between
/// two updates; one on such a body its own weight has stretched and stiffened (about four times
/// the weightless force at 4 mm), 0.5 mm; one on a stiffer volume term, which that iteration
/// leaves further from its balance, 0.3 mm.
double hapticRateReach_m(int newtonIterations, double bulkModulus_Pa, bool isHeavy,
                         const StrainEnergy& energy);

/// The time an update takes where the scene uses each one when it is done (latency 0): about
/// what one takes on one core of a desktop machine for the bundled body (s).
double hapticRateUpdateGuess_s(int newtonIterations);

/// The default poke's travel in such a scene past where the tool's axis meets the organ as it
/// opens (m): 7 mm into the liver, where the continuum reference still has its equilibrium (and,
/// under gravity, short of where the hanging liver's own equilibrium jumps).
inline constexpr double kHapticRateDefaultPokeIntoOrgan_m = 0.007;
/// The same travel along the tool where its axis misses the organ (m): from the bundled scene's
/// start, the same 7 mm into the liver.
inline constexpr double kHapticRateDefaultPokeDepth_m = 0.015;

/// The probe's speed limit for the scene with its tissue (m/s): its reach per update.
double hapticRateToolSpeed_m_s(const SceneDescription& scene, const StrainEnergy& energy);

/// The clearance within which the window's tool moves no faster than the scheme follows (m),
/// measured to the tet mesh's boundary (sim/ToolClearance.h). An update takes as candidates the
/// surface points within a millimetre of the probe where it starts and is in use until the next
/// comes in, two updates' time after it started: at the limit the probe travels two reaches
/// meanwhile, so the tool is down to that speed five updates' travel before it can touch.
inline constexpr double kHapticRateNearClearance_m = 0.003;

/// The window's tool motion limits in such a scene: the proxy's own, and the probe's speed limit
/// within kHapticRateNearClearance_m of the organ.
ToolMotionLimits hapticRateToolLimits(const SceneDescription& scene, const StrainEnergy& energy);

}  // namespace tissuesim
