// SPDX-License-Identifier: Apache-2.0
#pragma once
// The indentation test (analysis/IndentationExperiment.h) through the FEM at its own rate and
// the probe's contact at the haptic rate, as the organ poke's haptic-rate row runs it
// (analysis/OrganPokeExperiment.h, pokeOrganHapticRate): the whole block, its bottom held, on a
// grid graded towards the top face's centre (indentationBlockMesh), its tets made quadratic; the
// probe driven down the block's axis from above the top face at the settings' speed; the force
// on it at the setup's depths below the top face, to compare with indentFem's at the same
// depths (the reference's quarter of the block, its symmetry planes through the same axis).

#include "analysis/IndentationExperiment.h"
#include "analysis/OrganPokeExperiment.h"
#include "material/StrainEnergy.h"

namespace tissuesim {

/// The body's grid: cells of finest_m under the probe, each `growth` times the one before, at
/// most coarsest_m (m). The default: six cells across, three down (1,183 quadratic nodes), whose
/// updates take about the 60 ms the bundled FEM scenes give them (docs/performance.md).
struct IndentationBodyGrading {
  double finest_m = 0.0025;
  double growth = 2.5;
  double coarsest_m = 0.015;
};

/// @param contactSpacing_m the probe's penalty points on the quadratic surface about this far
///   apart (m), as a scene's (sim/HapticRateBody.h); 0: on each quadratic surface node, as
///   the references' (OrganPokeSetup::contactSpacing_m)
/// @throws std::invalid_argument on a grading or setting out of range (gradedGridLine's,
///   pokeOrganHapticRate's).
HapticRatePoke indentHapticRate(const StrainEnergy& energy, const IndentationSetup& setup,
                                const IndentationBodyGrading& grading, double bulkModulus_Pa,
                                double contactSpacing_m, const HapticRateSettings& settings);

}  // namespace tissuesim
