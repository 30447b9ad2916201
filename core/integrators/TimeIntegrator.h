// SPDX-License-Identifier: Apache-2.0
#pragma once
// The interface of a time integrator: advance a MechanicalState by one fixed time step.

#include <limits>
#include <optional>
#include <string>

#include "system/MechanicalSystem.h"

namespace tissuesim {

struct StepReport {
  int substeps = 1;                ///< explicit: substeps taken for stability
  int iterations = 0;              ///< implicit: Newton or quasi-Newton iterations
  int linearIterations = 0;        ///< implicit with CG: CG iterations over the whole step
  double residual_N = 0.0;         ///< implicit: max |r| at the end (N)
  double initialResidual_N = 0.0;  ///< implicit: max |r| at the step's start (predictor), N
  bool converged = true;           ///< implicit: residual under tolerance
  bool refused = false;            ///< the step was not taken (state unchanged): see `reason`
  bool isFinite = true;            ///< false when NaN or infinity appeared (state not advanced)
  double stableTimeStep_s = std::numeric_limits<double>::infinity();  ///< explicit bound
  ForceReport forces;  ///< what the last force evaluation saw
  /// explicit: the instrument contacts' impulses over the step (N s); the tool's mean force is
  /// this over dt. Unset where contacts are forces (the implicit integrators).
  std::optional<Eigen::Vector3d> toolImpulse_Ns;
  std::string reason;
};

/// Settings shared by the integrators.
struct IntegratorSettings {
  double massDamping_1_s = 0.0;  ///< alpha: damping force -alpha m v (1/s)
  // Explicit.
  int maxSubsteps = 64;          ///< refuse a step that would need more
  double stabilitySafety = 0.8;  ///< substep dt <= safety * 2 / omega_max
  // Implicit.
  int maxIterations = 20;          ///< Newton (or quasi-Newton) iterations per step
  double forceTolerance_N = 1e-6;  ///< converged when max |r| is below this
  /// Implicit (Newton and quasi-Newton): up to this many iterations past maxIterations while
  /// max |r| stays above extraIterationResidual_N (N).
  int extraIterations = 0;
  double extraIterationResidual_N = 1e-3;
  int historySize = 5;            ///< quasi-Newton: L-BFGS pairs kept
  double linearTolerance = 1e-6;  ///< CG: relative residual of each Newton linear solve
};

class TimeIntegrator {
 public:
  virtual ~TimeIntegrator() = default;
  /// Advances `state` by dt (s). On refusal or a non-finite result the state is left as it was
  /// and the report says why; the Mullins history is committed only after a good step.
  virtual StepReport step(MechanicalSystem& system, MechanicalState& state, double dt) = 0;
  virtual const char* name() const = 0;
};

}  // namespace tissuesim
