// SPDX-License-Identifier: Apache-2.0
#include "material/InverseLangevin.h"

#include <cmath>
#include <limits>
#include <numbers>

namespace tissuesim {
namespace {
// Below this beta the closed forms lose digits to cancellation; the Taylor series
// L = b/3 - b^3/45 + 2 b^5/945 - b^7/4725 is exact to double precision there.
constexpr double kSmallBeta = 1e-2;
}  // namespace

double langevin(double beta) {
  if (std::abs(beta) < kSmallBeta) {
    const double b2 = beta * beta;
    return beta * (1.0 / 3.0 - b2 * (1.0 / 45.0 - b2 * (2.0 / 945.0 - b2 / 4725.0)));
  }
  return 1.0 / std::tanh(beta) - 1.0 / beta;
}

double langevinSlope(double beta) {
  if (std::abs(beta) < kSmallBeta) {
    const double b2 = beta * beta;
    return 1.0 / 3.0 - b2 * (1.0 / 15.0 - b2 * (2.0 / 189.0 - b2 / 675.0));
  }
  // 1/sinh^2(b) = 4 e^{-2b} / (1 - e^{-2b})^2, which neither overflows nor cancels for large b.
  const double e = std::exp(-2.0 * std::abs(beta));
  const double cschSquared = 4.0 * e / ((1.0 - e) * (1.0 - e));
  return 1.0 / (beta * beta) - cschSquared;
}

double logSinh(double beta) {
  return beta + std::log1p(-std::exp(-2.0 * beta)) - std::numbers::ln2;
}

InverseLangevinValue inverseLangevinPuso(double r) {
  const double r3 = r * r * r;
  const double gap = 1.0 - r3;
  return {3.0 * r / gap, 3.0 * (1.0 + 2.0 * r3) / (gap * gap),
          18.0 * r * r * (2.0 + r3) / (gap * gap * gap)};
}

InverseLangevinValue inverseLangevinExact(double r) {
  if (r == 0.0) return {0.0, 3.0, 0.0};
  double beta = inverseLangevinPuso(r).beta;
  // Newton converges in a few steps from Puso's value (within a few per cent everywhere).
  for (int iteration = 0; iteration < 50; ++iteration) {
    const double step = (langevin(beta) - r) / langevinSlope(beta);
    beta -= step;
    if (std::abs(step) <= 4.0 * std::numeric_limits<double>::epsilon() * beta) break;
  }
  const double slope = langevinSlope(beta);  // L'(beta) = dr/dbeta
  // L''(beta) = -2/beta^3 + 2 coth(beta) / sinh^2(beta)
  double curvature;
  if (beta < kSmallBeta) {
    curvature = -2.0 * beta / 15.0;
  } else {
    const double e = std::exp(-2.0 * beta);
    const double cschSquared = 4.0 * e / ((1.0 - e) * (1.0 - e));
    curvature = -2.0 / (beta * beta * beta) + 2.0 * cschSquared / std::tanh(beta);
  }
  const double dBeta = 1.0 / slope;
  return {beta, dBeta, -curvature * dBeta * dBeta * dBeta};
}

}  // namespace tissuesim
