#pragma once
// Semi-implicit (symplectic) Euler with automatic substepping:
//
//   v_{n+1} = v_n + h M^-1 (f(x_n) - alpha M v_n),   x_{n+1} = x_n + h v_{n+1}
//
// Stable while h < 2 / omega_max. omega_max^2 is bounded each substep from the same pass that
// computes the forces (Gershgorin on M^-1 K, SpringForceField), so the step dt is split into
// ceil(dt / (safety * 2 / omega_max)) substeps, using the bound of the previous substep (the
// tangent stiffness changes little in one substep; the safety factor covers it). A step needing
// more than maxSubsteps is refused, never taken unstably.

#include "integrators/TimeIntegrator.h"

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

  IntegratorSettings m_settings;
  Eigen::Matrix3Xd m_force;
  Eigen::VectorXd m_nodeStiffness;
  Eigen::Matrix3Xd m_savedX;
  Eigen::Matrix3Xd m_savedV;
  double m_lastFrequencySquared = -1.0;  ///< < 0: not yet known
};

}  // namespace tissuesim
