#include "integrators/ImplicitEulerSolver.h"

#include <cmath>

namespace tissuesim {

StepReport ImplicitEulerSolver::step(MechanicalSystem& system, MechanicalState& state, double dt) {
  StepReport report;
  const double damping = 1.0 + m_settings.massDamping_1_s * dt;
  m_xHat = state.x + (dt / damping) * state.v;
  m_x = m_xHat;  // the inertial guess
  // Fixed DOFs stay where the caller put them.
  const std::vector<char>& fixed = system.fixedDofs();
  for (std::size_t d = 0; d < fixed.size(); ++d) {
    if (fixed[d] != 0) m_x.data()[d] = state.x.data()[d];
  }
  const NewtonReport newton =
      m_newton.solve(system, m_x, m_xHat, damping / (dt * dt), 0.0, m_settings.maxIterations,
                     m_settings.forceTolerance_N);
  report.iterations = newton.iterations;
  report.linearIterations = newton.linearIterations;
  report.residual_N = newton.residual_N;
  report.converged = newton.converged;
  report.forces = newton.forces;
  if (!m_x.allFinite() || !std::isfinite(newton.residual_N)) {
    report.isFinite = false;
    report.reason = "non-finite force or position in an implicit step; state rolled back";
    return report;
  }
  for (std::size_t d = 0; d < fixed.size(); ++d) {
    if (fixed[d] == 0) state.v.data()[d] = (m_x.data()[d] - state.x.data()[d]) / dt;
  }
  state.x.swap(m_x);
  system.springs().commitStretchHistory(state.x);
  return report;
}

}  // namespace tissuesim
