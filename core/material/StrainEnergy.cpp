// SPDX-License-Identifier: Apache-2.0
#include "material/StrainEnergy.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "material/InverseLangevin.h"
#include "numerics/GaussLegendre.h"

namespace tissuesim {
namespace {

/// Below this |I1 - 3| the energy and its secant come from quadrature of dW_T/dI1.
constexpr double kQuadratureBelowShift = 1e-2;

}  // namespace

StrainEnergy::StrainEnergy(const TissueParameters& parameters) : m_parameters(parameters) {
  const double n = m_parameters.chainSegmentsN;
  const double restChainStretch = 1.0 / std::sqrt(n);  // r at I1 = 3
  m_isoConstant = -isotropicInChainStretch(restChainStretch, /*withEnergy=*/true).energy;
  m_initialShearModulus = 2.0 * closedFormAtShift(0.0, /*withEnergy=*/false).dEnergy;
  m_locking = stretchesAtInvariant(n);
  // Keep at least half the gap between rest and locking, for N barely above 1.
  const double margin = std::min(kLockingMargin, 0.5 * (1.0 - restChainStretch));
  m_usableShift = 3.0 * n * (1.0 - margin) * (1.0 - margin) - 3.0;
  m_usable = stretchesAtInvariant(n * (1.0 - margin) * (1.0 - margin));
}

StretchRange StrainEnergy::stretchesAtInvariant(double k) {
  // Trigonometric roots of the depressed cubic t^3 - 3 k t + 2 = 0, then Newton polishing.
  const double scale = 2.0 * std::sqrt(k);
  const double angle = std::acos(std::clamp(-1.0 / (k * std::sqrt(k)), -1.0, 1.0)) / 3.0;
  double roots[2] = {scale * std::cos(angle - 2.0 * std::numbers::pi / 3.0),
                     scale * std::cos(angle)};
  for (double& root : roots) {
    for (int iteration = 0; iteration < 8; ++iteration) {
      const double value = root * root * root - 3.0 * k * root + 2.0;
      const double slope = 3.0 * root * root - 3.0 * k;
      if (slope == 0.0) break;
      root -= value / slope;
    }
  }
  return {roots[0], roots[1]};
}

EnergyInI1 StrainEnergy::isotropicInChainStretch(double r, bool withEnergy) const {
  const double n = m_parameters.chainSegmentsN;
  const double mu = m_parameters.mu_Pa;
  const InverseLangevinValue inv = m_parameters.inverseLangevin == InverseLangevin::Exact
                                       ? inverseLangevinExact(r)
                                       : inverseLangevinPuso(r);
  const double beta = inv.beta;
  const double b1 = inv.dBeta;
  const double b2 = inv.d2Beta;
  // coth, csch^2 and ln sinh from one exponential, stable for large beta.
  const double e = std::exp(-2.0 * beta);
  const double cothBeta = (1.0 + e) / (1.0 - e);
  const double cschSquared = 4.0 * e / ((1.0 - e) * (1.0 - e));

  // W = mu [ N (beta r + ln beta - ln sinh beta) - ln beta + ln r ]   (Eq. 3 without c)
  double energy = 0.0;
  if (withEnergy) {
    const double logSinhBeta = beta + std::log1p(-e) - std::numbers::ln2;
    const double logBeta = std::log(beta);
    energy = mu * (n * (beta * r + logBeta - logSinhBeta) - logBeta + std::log(r));
  }
  // dW/dr. With the exact inverse the N-bracket reduces to N beta (Eq. 15); with Puso's it
  // does not, and this is the derivative of the energy actually used (model.md).
  const double dEnergy =
      mu * (n * (b1 * r + beta + b1 / beta - b1 * cothBeta) - b1 / beta + 1.0 / r);
  const double d2Energy = mu * (n * (b2 * r + 2.0 * b1 + b2 / beta - b1 * b1 / (beta * beta) -
                                     b2 * cothBeta + b1 * b1 * cschSquared) -
                                b2 / beta + b1 * b1 / (beta * beta) - 1.0 / (r * r));
  return {energy, dEnergy, d2Energy};
}

SecantFromRest StrainEnergy::secantFromRest(double shift) const {
  if (std::abs(shift) >= kQuadratureBelowShift) {
    const EnergyInI1 w = closedFormAtShift(shift, /*withEnergy=*/true);
    const double secant = w.energy / shift;
    return {secant, (w.dEnergy - secant) / shift};
  }
  // Q = int_0^1 W'(3 + s shift) ds;  dQ/dI1 = int_0^1 s W''(3 + s shift) ds.
  SecantFromRest q{0.0, 0.0};
  for (std::size_t k = 0; k < kGaussLegendreNodes.size(); ++k) {
    const EnergyInI1 w = closedFormAtShift(kGaussLegendreNodes[k] * shift, /*withEnergy=*/false);
    q.value += kGaussLegendreWeights[k] * w.dEnergy;
    q.slope += kGaussLegendreWeights[k] * kGaussLegendreNodes[k] * w.d2Energy;
  }
  return q;
}

EnergyInI1 StrainEnergy::atInvariantShift(double shift) const {
  const bool isNearRest = std::abs(shift) < kQuadratureBelowShift;
  EnergyInI1 w = closedFormAtShift(shift, /*withEnergy=*/!isNearRest);
  if (isNearRest) w.energy = shift * secantFromRest(shift).value;
  return w;
}

EnergyInI1 StrainEnergy::closedFormAtShift(double shift, bool withEnergy) const {
  const double n = m_parameters.chainSegmentsN;
  const double f = m_parameters.fibreFraction;
  const double r = std::sqrt((3.0 + shift) / (3.0 * n));
  const double drdI = 1.0 / (6.0 * n * r);
  const double d2rdI2 = -drdI * drdI / r;
  const EnergyInI1 iso = isotropicInChainStretch(r, withEnergy);

  const double a1 = m_parameters.A1_Pa;
  const double a2 = m_parameters.A2_Pa;
  // W_aniso with I3 = 1 (Eq. 8).
  const double anisoEnergy = a1 / 3.0 * shift + a2 / 9.0 * shift * shift;
  const double anisoSlope = a1 / 3.0 + 2.0 * a2 / 9.0 * shift;
  const double anisoCurvature = 2.0 * a2 / 9.0;

  const double isoEnergy = iso.energy + m_isoConstant;
  const double isoSlope = iso.dEnergy * drdI;
  const double isoCurvature = iso.d2Energy * drdI * drdI + iso.dEnergy * d2rdI2;
  return {withEnergy ? (1.0 - f) * isoEnergy + f * anisoEnergy : 0.0,
          (1.0 - f) * isoSlope + f * anisoSlope, (1.0 - f) * isoCurvature + f * anisoCurvature};
}

HermiteNode StrainEnergy::stressAndSlope(double lambda) const {
  const EnergyInI1 w = closedFormAtShift(invariantShift(lambda), /*withEnergy=*/false);
  const double dI = invariantSlope(lambda);
  const double d2I = 2.0 + 4.0 / (lambda * lambda * lambda);
  return {w.dEnergy * dI, w.d2Energy * dI * dI + w.dEnergy * d2I};
}

UniaxialResponse StrainEnergy::uniaxial(double lambda) const {
  const double shift = invariantShift(lambda);
  const HermiteNode stress = stressAndSlope(lambda);
  const bool isNearRest = std::abs(shift) < kQuadratureBelowShift;
  const double energy = isNearRest ? shift * secantFromRest(shift).value
                                   : closedFormAtShift(shift, /*withEnergy=*/true).energy;
  return {energy, stress.value, stress.slope};
}

}  // namespace tissuesim
