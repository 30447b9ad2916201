// SPDX-License-Identifier: Apache-2.0
#pragma once
// The integrator a scene names (physics.integrator), built from its settings: one place that
// maps the names to the schemes, for the simulation and the measurements that step the same way.
//
//   "implicit"      backward Euler, Newton with CG (ImplicitEulerSolver)
//   "quasi-newton"  backward Euler, L-BFGS (QuasiNewtonSolver)
//   "explicit"      symplectic Euler with stability substeps (SymplecticEulerSolver)

#include <memory>
#include <string>

#include "integrators/TimeIntegrator.h"

namespace tissuesim {

/// @throws std::invalid_argument for a name not listed above.
std::unique_ptr<TimeIntegrator> makeIntegrator(const std::string& name,
                                               const IntegratorSettings& settings);

}  // namespace tissuesim
