// SPDX-License-Identifier: Apache-2.0
#include "integrators/SymplecticEulerSolver.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "parallel/NodeRanges.h"

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

double SymplecticEulerSolver::stableStepBound(double largestStiffnessPerMass,
                                              double massDamping_1_s) {
  // h_max(omega^2) = (sqrt(alpha^2 + 4 omega^2) - alpha) / omega^2
  //                = 4 / (sqrt(alpha^2 + 4 omega^2) + alpha)   (no cancellation)
  // falls as omega^2 grows, so the nodes' smallest h_max is the one at their largest omega^2:
  // one square root a substep, not one per node (at the liver's size the per-node loop was about
  // a tenth of the substep). At omega = 0 it is 2 / alpha, the damping's own limit.
  const double gamma = massDamping_1_s;
  const double omega2 = 2.0 * largestStiffnessPerMass;
  if (omega2 > 0.0) return 4.0 / (std::sqrt(gamma * gamma + 4.0 * omega2) + gamma);
  return gamma > 0.0 ? 2.0 / gamma : std::numeric_limits<double>::infinity();
}

double SymplecticEulerSolver::largestStiffnessPerMass(const Eigen::VectorXd& nodeStiffness,
                                                      const Eigen::VectorXd& mass,
                                                      Eigen::Index begin, Eigen::Index end) {
  double largest = 0.0;
  for (Eigen::Index i = begin; i < end; ++i)
    largest = std::max(largest, nodeStiffness[i] / mass[i]);
  return largest;
}

double SymplecticEulerSolver::stableTimeStep(const MechanicalSystem& system,
                                             const Eigen::Matrix3Xd& x, double safety) {
  Eigen::Matrix3Xd f(3, x.cols());
  Eigen::VectorXd nodeStiffness(x.cols());
  system.forcesAndNodeStiffness(x, f, nodeStiffness);
  const Eigen::VectorXd& mass = system.mesh().nodeMass_kg;
  return safety *
         stableStepBound(largestStiffnessPerMass(nodeStiffness, mass, 0, mass.size()), 0.0);
}

StepReport SymplecticEulerSolver::step(MechanicalSystem& system, MechanicalState& state,
                                       double dt) {
  const Eigen::Index nodes = system.mesh().nodeCount();
  ensureBuffers(nodes);
  StepReport report;
  const Eigen::VectorXd& mass = system.mesh().nodeMass_kg;
  const double alpha = m_settings.massDamping_1_s;
  const std::vector<char>& fixed = system.fixedDofs();

  ForkJoinPool* const pool = system.springs().threadPool();
  // Each substep's force pass refreshes the bound for the next. The last one came from the state
  // before the previous step's last move: when it alone would refuse this step (a spike of one
  // pass), it is taken again at this step's own start before the step is refused.
  const auto stableStep = [&] { return m_settings.stabilitySafety * m_lastStableStep; };
  if (m_lastStableStep < 0.0 || std::ceil(dt / stableStep()) > m_settings.maxSubsteps) {
    system.forcesAndNodeStiffness(state.x, m_force, m_nodeStiffness);
    m_lastStableStep =
        stableStepBound(largestStiffnessPerMass(m_nodeStiffness, mass, 0, nodes), alpha);
  }
  report.stableTimeStep_s = stableStep();
  const double needed = std::ceil(dt / report.stableTimeStep_s);
  if (needed > m_settings.maxSubsteps) {
    report.refused = true;
    report.substeps = 0;
    report.reason = "explicit step refused: dt = " + std::to_string(dt) + " s needs " +
                    std::to_string(static_cast<long long>(needed)) + " substeps (stable step " +
                    std::to_string(report.stableTimeStep_s) + " s), more than the limit of " +
                    std::to_string(m_settings.maxSubsteps);
    return report;
  }
  m_savedX = state.x;
  m_savedV = state.v;

  double remaining = dt;
  int substeps = 0;
  Eigen::Vector3d toolImpulse_Ns = Eigen::Vector3d::Zero();
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
    // The velocities, and the next bound from this pass's node stiffness, in one node-wise pass.
    forEachNodeRange(pool, nodes, [&](int range, Eigen::Index begin, Eigen::Index end) {
      for (Eigen::Index i = begin; i < end; ++i) {
        for (int axis = 0; axis < 3; ++axis) {
          if (fixed[static_cast<std::size_t>(3 * i + axis)] != 0) continue;
          double& v = state.v(axis, i);
          v += h * (m_force(axis, i) / mass[i] - alpha * v);
        }
      }
      m_rangeLargest[static_cast<std::size_t>(range)] =
          largestStiffnessPerMass(m_nodeStiffness, mass, begin, end);
    });
    const double largest = *std::max_element(m_rangeLargest.begin(), m_rangeLargest.end());
    m_lastStableStep = stableStepBound(largest, alpha);
    toolImpulse_Ns += system.contacts.applyImpulses(state.x, mass, fixed, h, state.v);
    forEachNodeRange(pool, nodes, [&](int, Eigen::Index begin, Eigen::Index end) {
      for (Eigen::Index i = begin; i < end; ++i) {
        for (int axis = 0; axis < 3; ++axis) {
          if (fixed[static_cast<std::size_t>(3 * i + axis)] == 0)
            state.x(axis, i) += h * state.v(axis, i);
        }
      }
    });
    remaining -= h;
  }
  report.substeps = substeps;
  report.toolImpulse_Ns = toolImpulse_Ns;
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
