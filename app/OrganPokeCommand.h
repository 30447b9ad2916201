// SPDX-License-Identifier: Apache-2.0
#pragma once
// `tissuesim organ-poke`: a scene's organ, weightless, poked along its instrument's axis from
// the instrument's start, through the continuum reference (core/analysis/OrganPokeExperiment.h,
// on a conformal tet mesh of the drawn surface) and through the simulator as the scene sets it
// up (its mesh, model, volume term, contact and integrator, the probe at a slow pace); the force
// on the probe at each depth below the surface and the simulator's error against the reference.

#include <CLI/CLI.hpp>

namespace tissuesim::app {

void registerOrganPokeCommand(CLI::App& app);

}  // namespace tissuesim::app
