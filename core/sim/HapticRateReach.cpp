// SPDX-License-Identifier: Apache-2.0
#include "sim/HapticRateReach.h"

#include "fem/FemModel.h"

namespace tissuesim {
namespace {

/// The reach measured on the liver poke (docs/performance-details.md, "One Newton iteration an
/// update on a softer volume term"): 0.6 mm held within 10 % and 0.75 mm did not, with one
/// iteration at a tenth of the reference's bulk modulus or less, or with two at the
/// reference's; with one at the reference's, 0.3 mm held and 0.45 mm did not. Under gravity, on
/// the default scene's tray, one iteration at a tenth held 0.3 mm and punctured the surface at
/// 0.6 mm, where two held 0.6 mm (a poke 4 mm deep); since each update hands its contact the
/// body's stiffening, one holds 0.525 mm within 6 % at 1 to 7 mm (docs/performance-details.md,
/// "The body's stiffening between updates"), and 0.6 mm reads 11 % soft at 2 mm. Where the
/// first touch falls between two updates decides the first millimetre: until the first update
/// under load comes in, the body at rest answers, linearly. Swept over the touch's phase, with
/// depths below the drawn surface as the reference's, 0.36 mm an update holds it within 10 %
/// and 0.39 mm does not ("The window's tool: slowed near the organ, not everywhere").
constexpr double kReach_m = 0.00036;
constexpr double kOneIterationHeavyReach_m = 0.0005;
constexpr double kOneIterationShortReach_m = 0.0003;
constexpr double kSoftVolumeShare = 0.1;
/// An update's Newton iteration on the bundled body, on one core (s): about 40 ms measured, with
/// the linearisation's solves.
constexpr double kIterationGuess_s = 0.05;

}  // namespace

double hapticRateReach_m(int newtonIterations, double bulkModulus_Pa, bool isHeavy,
                         const StrainEnergy& energy) {
  const bool isSoftVolume = bulkModulus_Pa <= kSoftVolumeShare * defaultFemBulkModulus(energy);
  if (newtonIterations >= 2) return kReach_m;
  if (!isSoftVolume) return kOneIterationShortReach_m;
  return isHeavy ? kOneIterationHeavyReach_m : kReach_m;
}

double hapticRateUpdateGuess_s(int newtonIterations) {
  return kIterationGuess_s * newtonIterations;
}

double hapticRateToolSpeed_m_s(const SceneDescription& scene, const StrainEnergy& energy) {
  const double updateEvery_s = scene.femUpdateLatency_s > 0.0
                                   ? scene.femUpdateLatency_s
                                   : hapticRateUpdateGuess_s(scene.newtonIterations);
  const bool isHeavy = scene.gravity_m_s2.squaredNorm() > 0.0;
  return hapticRateReach_m(scene.newtonIterations, scene.bulkModulus_Pa, isHeavy, energy) /
         updateEvery_s;
}

ToolMotionLimits hapticRateToolLimits(const SceneDescription& scene, const StrainEnergy& energy) {
  ToolMotionLimits limits;
  limits.nearSpeed_m_s = hapticRateToolSpeed_m_s(scene, energy);
  limits.nearClearance_m = kHapticRateNearClearance_m;
  return limits;
}

}  // namespace tissuesim
