// SPDX-License-Identifier: Apache-2.0
#pragma once
// The virtual tensile test (TensileExperiment.h: the same specimen, grips and protocol) through the
// FEM reference (fem/FemModel.h) instead of the spring network. The FEM is hyperelastic, with
// no Mullins softening: every branch follows the virgin curve, so it is compared with sedf's
// loading branches only. The specimen's tets become quadratic ones; engineering stress is the
// grip's reaction over the initial section.

#include <vector>

#include "analysis/TensileExperiment.h"
#include "analysis/UniaxialExperiment.h"
#include "material/StrainEnergy.h"

namespace tissuesim {

struct FemTensileStats {
  int nodes = 0;
  int elements = 0;
  int worstIterations = 0;
  double worstResidual_N = 0.0;
  int unconvergedPoints = 0;
  double minVolumeRatio = 1.0;  ///< over every element and point
  double maxVolumeRatio = 1.0;
};

/// Runs the protocol (lambda_max in (1, the usable range's upper end]) with bulk modulus kappa
/// (Pa, > 0).
/// @throws std::invalid_argument.
std::vector<CurveBranch> runFemTensileTest(const StrainEnergy& energy,
                                           const TensileSpecimen& specimen, double bulkModulus_Pa,
                                           const UniaxialProtocol& protocol,
                                           FemTensileStats* stats = nullptr);

}  // namespace tissuesim
