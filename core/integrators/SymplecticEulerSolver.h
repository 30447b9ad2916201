// SPDX-License-Identifier: Apache-2.0
#pragma once
// Semi-implicit (symplectic) Euler with automatic substepping:
//
//   v_{n+1} = v_n + h M^-1 (f(x_n) - alpha M v_n),   x_{n+1} = x_n + h v_{n+1}
//
// With the explicit mass damping alpha a node's oscillator is stable while
// omega^2 h^2 + 2 alpha h <= 4 (Jury's test on the step's 2x2 map; h < 2 / omega without
// damping), so h_max = (sqrt(alpha^2 + 4 omega^2) - alpha) / omega^2 over the nodes (it falls
// as omega^2 grows: the node with the largest omega^2 sets it), with
// omega^2 bounded each substep from the same pass that computes the forces (Gershgorin on
// M^-1 K: 2 K_i / m_i, from SpringForceField). The instrument's contacts are impulses after
// the velocity update, each stepped by backward Euler on its own (PenaltyContactSet::
// applyImpulses), so they bound nothing. The step dt is split into ceil(dt / (safety h_max))
// substeps, using the bound of the previous substep (the tangent stiffness changes little in one
// substep; the safety factor covers it). A step needing more than maxSubsteps by the bound at its
// own start, or running out of them, is refused, never taken unstably.

#include <array>

#include "integrators/TimeIntegrator.h"
#include "parallel/NodeRanges.h"

namespace tissuesim {

class SymplecticEulerSolver final : public TimeIntegrator {
 public:
  explicit SymplecticEulerSolver(IntegratorSettings settings) : m_settings(settings) {}
  StepReport step(MechanicalSystem& system, MechanicalState& state, double dt) override;
  const char* name() const override { return "explicit"; }

  /// The stable step (s) for a system at state x, from the current bound (for reports).
  static double stableTimeStep(const MechanicalSystem& system, const Eigen::Matrix3Xd& x,
                               double safety);

 private:
  void ensureBuffers(Eigen::Index nodeCount);
  /// h_max (s) from the nodes' largest stiffness bound over mass, max_i K_i / m_i (1/s^2), and
  /// the mass damping (1/s).
  static double stableStepBound(double largestStiffnessPerMass, double massDamping_1_s);
  /// max K_i / m_i over nodes [begin, end) (1/s^2; 0 when none is positive).
  static double largestStiffnessPerMass(const Eigen::VectorXd& nodeStiffness,
                                        const Eigen::VectorXd& mass, Eigen::Index begin,
                                        Eigen::Index end);

  IntegratorSettings m_settings;
  Eigen::Matrix3Xd m_force;
  Eigen::VectorXd m_nodeStiffness;
  Eigen::Matrix3Xd m_savedX;
  Eigen::Matrix3Xd m_savedV;
  double m_lastStableStep = -1.0;  ///< h_max of the last bound (s); < 0: not yet known
  std::array<double, kNodeRanges> m_rangeLargest{};  ///< per-range max K_i / m_i (1/s^2)
};

}  // namespace tissuesim
