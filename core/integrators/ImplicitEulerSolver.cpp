// SPDX-License-Identifier: Apache-2.0
#include "integrators/ImplicitEulerSolver.h"

#include <cmath>

#include "parallel/NodeRanges.h"

namespace tissuesim {

StepReport ImplicitEulerSolver::step(MechanicalSystem& system, MechanicalState& state, double dt) {
  StepReport report;
  const double damping = 1.0 + m_settings.massDamping_1_s * dt;
  ForkJoinPool* const pool = system.springs().threadPool();
  const Eigen::Index nodes = state.x.cols();
  const std::vector<char>& fixed = system.fixedDofs();
  m_xHat.resize(3, nodes);  // no-ops after the first step
  m_x.resize(3, nodes);
  m_v.resize(3, nodes);
  forEachNodeRange(pool, nodes, [&](int, Eigen::Index begin, Eigen::Index end) {
    const Eigen::Index count = end - begin;
    m_xHat.middleCols(begin, count) =
        state.x.middleCols(begin, count) + (dt / damping) * state.v.middleCols(begin, count);
    m_x.middleCols(begin, count) = m_xHat.middleCols(begin, count);  // the inertial guess
    // Fixed DOFs stay where the caller put them.
    for (Eigen::Index d = 3 * begin; d < 3 * end; ++d) {
      if (fixed[static_cast<std::size_t>(d)] != 0) m_x.data()[d] = state.x.data()[d];
    }
  });
  const NewtonReport newton = m_newton.solve(system, m_x, m_xHat, damping / (dt * dt), 0.0,
                                             m_settings.maxIterations, m_settings.forceTolerance_N);
  report.iterations = newton.iterations;
  report.linearIterations = newton.linearIterations;
  report.residual_N = newton.residual_N;
  report.initialResidual_N = newton.initialResidual_N;
  report.converged = newton.converged;
  report.forces = newton.forces;
  // The new velocities, and whether every position is finite, in one node-wise pass.
  NodeRangeFlags isRangeFinite{};
  forEachNodeRange(pool, nodes, [&](int range, Eigen::Index begin, Eigen::Index end) {
    bool isFinite = true;
    for (Eigen::Index d = 3 * begin; d < 3 * end; ++d) {
      const double position = m_x.data()[d];
      isFinite = isFinite && std::isfinite(position);
      m_v.data()[d] = fixed[static_cast<std::size_t>(d)] != 0 ? state.v.data()[d]
                                                              : (position - state.x.data()[d]) / dt;
    }
    isRangeFinite[static_cast<std::size_t>(range)] = isFinite;
  });
  if (!allRanges(isRangeFinite) || !std::isfinite(newton.residual_N)) {
    report.isFinite = false;
    report.reason = "non-finite force or position in an implicit step; state rolled back";
    return report;
  }
  state.v.swap(m_v);
  state.x.swap(m_x);
  system.springs().commitStretchHistory(state.x);
  return report;
}

}  // namespace tissuesim
