// SPDX-License-Identifier: Apache-2.0
#include "analysis/NetworkCalibration.h"

#include "analysis/TensileExperiment.h"

namespace tissuesim {

double simulatorStiffnessScale(const StrainEnergy& energy, const StiffnessTable& table,
                               double bulkModulus_Pa) {
  if (!(bulkModulus_Pa > 0.0)) {
    return TensileExperiment(energy, table, TensileSpecimen{})
        .smallStrainCalibration(energy.initialShearModulus());
  }
  TensileSpecimen specimen;
  specimen.cellsAcrossThickness = 1;
  return TensileExperiment(energy, table, specimen)
      .volumeTermCalibration(energy.initialShearModulus(), bulkModulus_Pa);
}

}  // namespace tissuesim
