// SPDX-License-Identifier: Apache-2.0
#pragma once
// A penalty's energy e(g), de/dg and d2e/dg2 per unit stiffness (m^2, m, 1) for a gap g (m): k g^2
// / 2 made twice differentiable at contact by a cubic over the first kPenaltySmoothing_m of
// penetration, so Newton meets no kink in the stiffness as points come into contact:
//
//   g >= 0: 0;   -d <= g < 0: -g^3 / (6 d);   g < -d: (g + d/2)^2 / 2 + d^2 / 24.

namespace tissuesim {

struct PenaltyTerms {
  double energy;
  double slope;
  double curvature;
};

inline constexpr double kPenaltySmoothing_m = 1e-6;

inline PenaltyTerms smoothedPenalty(double g) {
  constexpr double d = kPenaltySmoothing_m;
  if (!(g < 0.0)) return {0.0, 0.0, 0.0};
  if (g > -d) return {-g * g * g / (6.0 * d), -g * g / (2.0 * d), -g / d};
  return {0.5 * (g + 0.5 * d) * (g + 0.5 * d) + d * d / 24.0, g + 0.5 * d, 1.0};
}

}  // namespace tissuesim
