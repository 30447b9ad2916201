// SPDX-License-Identifier: Apache-2.0
#pragma once
// The spring network's calibration as the simulator applies it: the factor on every spring's
// volume share V_e that makes a Kuhn lattice of springs as stiff as the continuum it stands for
// (docs/model.md; docs/scene-file.md, "The volume term"). Without a volume term it is the
// small-strain calibration, the pure function springs/SmallStrainCalibration on the paper's
// specimen. With one, that factor is refitted to the continuum's loading over the paper's cycles,
// which takes the network's nonlinear statics (TensileExperiment::volumeTermCalibration): so
// this sits with the virtual experiments, above the mechanical system whose statics it solves,
// and below sim/, which applies it.

#include "material/StiffnessTable.h"
#include "material/StrainEnergy.h"

namespace tissuesim {

/// The factor on every spring's V_e that the simulator applies (Simulation, and the indentation
/// and trade measurements that stand for it): the springs' small-strain calibration on the
/// paper's specimen, fitted with the volume term in place when bulkModulus_Pa > 0
/// (volumeTermCalibration on the specimen one cell across: two runs of a small specimen).
double simulatorStiffnessScale(const StrainEnergy& energy, const StiffnessTable& table,
                               double bulkModulus_Pa);

}  // namespace tissuesim
