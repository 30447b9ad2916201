// SPDX-License-Identifier: Apache-2.0
#pragma once
// The indentation test (analysis/IndentationExperiment.h) through the FEM at its own rate and
// the probe's contact at the haptic rate, as the organ poke's haptic-rate row runs it
// (analysis/OrganPokeExperiment.h, pokeOrganHapticRate): the whole block, its bottom held, its
// body refined towards the top face's centre as a scene refines its organ where the tool aims
// (tet_mesh.refine_towards_tool: mesh/TetRefinement.h), its tets made quadratic; the probe driven
// down the block's axis from above the top face at the settings' speed; the force on it at the
// setup's depths below the top face, to compare with indentFem's at the same depths (the
// reference's quarter of the block, its symmetry planes through the same axis).

#include "analysis/IndentationExperiment.h"
#include "analysis/OrganPokeExperiment.h"
#include "material/StrainEnergy.h"
#include "mesh/TetMesh.h"

namespace tissuesim {

/// The body: the block in cubes of about coarsest_m (Kuhn's six tets each), refined by bisection
/// towards the top face's centre to edges of finest_m there, growing by `growth` (m per m) away
/// from it (mesh/TetRefinement.h's grading). The default: a body whose updates fit in the time the
/// bundled FEM scenes give them (docs/performance-details.md, "The block at the haptic rate").
struct IndentationBodyGrading {
  double finest_m = 0.0015;
  double growth = 1.0;
  double coarsest_m = 0.015;
};

/// The block's body at rest (linear tets). @throws std::invalid_argument on a grading out of
/// range (refineTetMesh's).
TetMesh indentationBody(const IndentationSetup& setup, const IndentationBodyGrading& grading);

/// @param contactSpacing_m the probe's penalty points on the quadratic surface about this far
///   apart (m), as a scene's (sim/HapticRateBody.h); 0: on each quadratic surface node, as
///   the references' (OrganPokeSetup::contactSpacing_m)
/// @throws std::invalid_argument on a grading or setting out of range (indentationBody's,
///   pokeOrganHapticRate's).
HapticRatePoke indentHapticRate(const StrainEnergy& energy, const IndentationSetup& setup,
                                const IndentationBodyGrading& grading, double bulkModulus_Pa,
                                double contactSpacing_m, const HapticRateSettings& settings);

}  // namespace tissuesim
