// SPDX-License-Identifier: Apache-2.0
#include "integrators/IntegratorChoice.h"

#include <stdexcept>

#include "integrators/ImplicitEulerSolver.h"
#include "integrators/QuasiNewtonSolver.h"
#include "integrators/SymplecticEulerSolver.h"

namespace tissuesim {

std::unique_ptr<TimeIntegrator> makeIntegrator(const std::string& name,
                                               const IntegratorSettings& settings) {
  if (name == "implicit")
    return std::make_unique<ImplicitEulerSolver>(settings, LinearSolverKind::ConjugateGradient);
  if (name == "quasi-newton") return std::make_unique<QuasiNewtonSolver>(settings);
  if (name == "explicit") return std::make_unique<SymplecticEulerSolver>(settings);
  throw std::invalid_argument("unknown integrator \"" + name +
                              "\"; expected implicit, quasi-newton or explicit");
}

}  // namespace tissuesim
