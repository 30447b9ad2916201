#include "integrators/SymplecticEulerSolver.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tissuesim {

void SymplecticEulerSolver::ensureBuffers(Eigen::Index nodeCount) {
  if (m_force.cols() != nodeCount) {
    m_force.resize(3, nodeCount);
    m_nodeStiffness.resize(nodeCount);
    m_savedX.resize(3, nodeCount);
    m_savedV.resize(3, nodeCount);
    m_lastStableStep = -1.0;
  }
}

double SymplecticEulerSolver::stableStepBound(const Eigen::VectorXd& nodeStiffness,
                                              const Eigen::VectorXd& mass, double massDamping_1_s) {
  double bound = std::numeric_limits<double>::infinity();
  const double gamma = massDamping_1_s;
  for (Eigen::Index i = 0; i < mass.size(); ++i) {
    const double omega2 = 2.0 * nodeStiffness[i] / mass[i];
    if (omega2 > 0.0) {
      bound = std::min(bound, (std::sqrt(gamma * gamma + 4.0 * omega2) - gamma) / omega2);
    } else if (gamma > 0.0) {
      bound = std::min(bound, 2.0 / gamma);
    }
  }
  return bound;
}

double SymplecticEulerSolver::stableTimeStep(const MechanicalSystem& system,
                                             const Eigen::Matrix3Xd& x, double safety) {
  Eigen::Matrix3Xd f(3, x.cols());
  Eigen::VectorXd nodeStiffness(x.cols());
  system.forcesAndNodeStiffness(x, f, nodeStiffness);
  return safety * stableStepBound(nodeStiffness, system.mesh().nodeMass_kg, 0.0);
}

StepReport SymplecticEulerSolver::step(MechanicalSystem& system, MechanicalState& state,
                                       double dt) {
  const Eigen::Index nodes = system.mesh().nodeCount();
  ensureBuffers(nodes);
  StepReport report;
  const Eigen::VectorXd& mass = system.mesh().nodeMass_kg;
  const double alpha = m_settings.massDamping_1_s;
  const std::vector<char>& fixed = system.fixedDofs();

  // Each substep's force pass refreshes the bound for the next.
  const auto refreshBound = [&] { m_lastStableStep = stableStepBound(m_nodeStiffness, mass, alpha); };
  if (m_lastStableStep < 0.0) {
    system.forcesAndNodeStiffness(state.x, m_force, m_nodeStiffness);
    refreshBound();
  }
  const auto stableStep = [&] { return m_settings.stabilitySafety * m_lastStableStep; };
  report.stableTimeStep_s = stableStep();
  const double needed = std::ceil(dt / report.stableTimeStep_s);
  if (needed > m_settings.maxSubsteps) {
    report.refused = true;
    report.substeps = 0;
    report.reason = "explicit step refused: dt = " + std::to_string(dt) +
                    " s needs " + std::to_string(static_cast<long long>(needed)) +
                    " substeps (stable step " + std::to_string(report.stableTimeStep_s) +
                    " s), more than the limit of " + std::to_string(m_settings.maxSubsteps);
    return report;
  }
  m_savedX = state.x;
  m_savedV = state.v;

  double remaining = dt;
  int substeps = 0;
  while (remaining > 1e-12 * dt) {
    // Substeps of equal length within what is left, each within the latest bound.
    const double stable = stableStep();
    const int pieces = std::max(1, static_cast<int>(std::ceil(remaining / stable - 1e-12)));
    const double h = remaining / pieces;
    if (++substeps > m_settings.maxSubsteps) {
      state.x = m_savedX;
      state.v = m_savedV;
      report.refused = true;
      report.reason = "explicit step refused: the stiffness rose during the step beyond what " +
                      std::to_string(m_settings.maxSubsteps) + " substeps can integrate";
      return report;
    }
    report.forces = system.forcesAndNodeStiffness(state.x, m_force, m_nodeStiffness);
    refreshBound();
    for (Eigen::Index i = 0; i < nodes; ++i) {
      for (int axis = 0; axis < 3; ++axis) {
        if (fixed[static_cast<std::size_t>(3 * i + axis)] != 0) continue;
        double& v = state.v(axis, i);
        v += h * (m_force(axis, i) / mass[i] - alpha * v);
      }
    }
    system.contacts.applyImpulses(state.x, mass, fixed, h, state.v);
    for (Eigen::Index i = 0; i < nodes; ++i) {
      for (int axis = 0; axis < 3; ++axis) {
        if (fixed[static_cast<std::size_t>(3 * i + axis)] == 0) state.x(axis, i) += h * state.v(axis, i);
      }
    }
    remaining -= h;
  }
  report.substeps = substeps;
  if (!state.isFinite()) {
    state.x = m_savedX;
    state.v = m_savedV;
    report.isFinite = false;
    report.reason = "non-finite position or velocity after an explicit step; state rolled back";
    return report;
  }
  system.springs().commitStretchHistory(state.x);
  return report;
}

}  // namespace tissuesim
