// SPDX-License-Identifier: Apache-2.0
#pragma once
// The net force a step's iterations may leave on a node before the step counts as unconverged
// (an instability event): above a thousandth of the newton a trainee feels and above a hundredth
// of the force the step applies (the instrument's, pushing and pulling). A real-time step stops
// at its iteration budget, and the linearised step's residual grows with the load; what it leaves
// is carried into the next step, not lost. Judged against the absolute threshold alone, a 4 cm
// poke reported 18 such steps (residuals of 1-21 mN under a force of 1.9 N), none an
// instability. The springs' steps (sim/Simulation.cpp) and the haptic-rate contact's
// (sim/HapticRateBody.h) both take it.

namespace tissuesim {

inline constexpr double kUnconvergedResidual_N = 1e-3;
inline constexpr double kUnconvergedRelativeResidual = 1e-2;

/// Whether residual_N (N, the largest left on a node) under a step force of load_N (N) counts.
inline bool isUnconvergedResidual(double residual_N, double load_N) {
  return residual_N > kUnconvergedResidual_N && residual_N > kUnconvergedRelativeResidual * load_N;
}

}  // namespace tissuesim
