// SPDX-License-Identifier: Apache-2.0
#include "sim/HapticRateReach.h"

#include "fem/FemModel.h"

namespace tissuesim {

double hapticRateReach_m(int newtonIterations, double bulkModulus_Pa, const StrainEnergy& energy) {
  const bool isSoftVolume = bulkModulus_Pa <= 0.1 * defaultFemBulkModulus(energy);
  return newtonIterations >= 2 || isSoftVolume ? 0.0006 : 0.0003;
}

double hapticRateUpdateGuess_s(int newtonIterations) { return 0.05 * newtonIterations; }

double hapticRateToolSpeed_m_s(const SceneDescription& scene, const StrainEnergy& energy) {
  const double updateEvery_s = scene.femUpdateLatency_s > 0.0
                                   ? scene.femUpdateLatency_s
                                   : hapticRateUpdateGuess_s(scene.newtonIterations);
  return hapticRateReach_m(scene.newtonIterations, scene.bulkModulus_Pa, energy) / updateEvery_s;
}

}  // namespace tissuesim
