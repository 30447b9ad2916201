// SPDX-License-Identifier: Apache-2.0
#pragma once
// Implicit (backward) Euler, solved by Newton (NewtonSolver):
//
//   M (v_{n+1} - v_n) / h = f(x_{n+1}) - alpha M v_{n+1},   x_{n+1} = x_n + h v_{n+1}
//   <=>  (1 + alpha h) / h^2 M (x - x_hat) - f(x) = 0,   x_hat = x_n + h v_n / (1 + alpha h)
//
// Unconditionally stable for the PSD-projected, line-searched Newton iteration; it dissipates
// energy (numerical damping grows with h). Baraff and Witkin 1998 take one Newton iteration;
// here iterations run to `forceTolerance_N` or `maxIterations`, whichever comes first.

#include "integrators/TimeIntegrator.h"
#include "system/NewtonSolver.h"

namespace tissuesim {

class ImplicitEulerSolver final : public TimeIntegrator {
 public:
  ImplicitEulerSolver(IntegratorSettings settings, LinearSolverKind linear)
      : m_settings(settings), m_newton(linear, settings.linearTolerance) {
    m_newton.setExtraIterations(settings.extraIterations, settings.extraIterationResidual_N);
  }
  StepReport step(MechanicalSystem& system, MechanicalState& state, double dt) override;
  const char* name() const override { return "implicit"; }

 private:
  IntegratorSettings m_settings;
  NewtonSolver m_newton;
  Eigen::Matrix3Xd m_xHat, m_x, m_v;
};

}  // namespace tissuesim
