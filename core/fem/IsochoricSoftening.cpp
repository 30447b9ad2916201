// SPDX-License-Identifier: Apache-2.0
#include "fem/IsochoricSoftening.h"

#include <algorithm>
#include <cmath>

#include "numerics/GaussLegendre.h"

namespace tissuesim {
namespace {

/// m = sqrt(lambda^4 + 2 lambda^-2) (Eq. 20) at I1bar - 3 = shift, and dm/dI = (lambda^3 + 1) /
/// (lambda m) (dm/dlambda = 2 (lambda^3 - lambda^-3) / m over dI/dlambda = 2 lambda - 2 lambda^-2,
/// with the common factor lambda^3 - 1 taken out: finite at rest).
struct Measure {
  double value;
  double slope;
};
Measure measureOfShift(double shift) {
  const double lambda = uniaxialStretchOfShift(shift);
  const double inverse = 1.0 / lambda;
  const double m = std::sqrt(lambda * lambda * lambda * lambda + 2.0 * inverse * inverse);
  return {m, (lambda * lambda * lambda + 1.0) * inverse / m};
}

/// The integral of F W_T' over [from, to] (I - 3, below the peak) where it is smooth: F has a
/// root's steepness at the peak (q falls to 0 as I_p - I does), and the stretch one at rest
/// (lambda - 1 ~ sqrt(I - 3)), so the upper half of [0, I_p - 3] is taken in r = sqrt(I_p - I)
/// and the lower in v = sqrt(I - 3), each side of the rounded onset apart.
double softenedWork(const StrainEnergy& energy, const StressSoftening& softening,
                    const IsochoricPeak& peak, double from, double to) {
  const auto integrand = [&](double at) {
    return isochoricSofteningFactor(softening, at, peak) *
           energy.slopesAtInvariantShift(at).dEnergy;
  };
  // g over [a, b] within one piece: in r above the half, in v below it.
  const double half = 0.5 * peak.shift;
  const auto piece = [&](double a, double b) {
    if (!(b > a)) return 0.0;
    const bool isUpper = a >= half;
    const double u0 = isUpper ? std::sqrt(peak.shift - b) : std::sqrt(a);
    const double u1 = isUpper ? std::sqrt(peak.shift - a) : std::sqrt(b);
    double sum = 0.0;
    for (std::size_t k = 0; k < kGaussLegendreNodes.size(); ++k) {
      const double u = u0 + kGaussLegendreNodes[k] * (u1 - u0);
      sum += kGaussLegendreWeights[k] * 2.0 * u * integrand(isUpper ? peak.shift - u * u : u * u);
    }
    return sum * (u1 - u0);
  };
  double breaks[4] = {from, std::clamp(half, from, to), std::clamp(peak.onsetShift, from, to), to};
  std::sort(breaks, breaks + 4);
  return piece(breaks[0], breaks[1]) + piece(breaks[1], breaks[2]) + piece(breaks[2], breaks[3]);
}

}  // namespace

double uniaxialStretchOfShift(double shift) {
  // The largest root of lambda^3 - I lambda + 2 = 0, I = 3 + shift, trigonometrically (three
  // real roots for I >= 3; the largest is 1 at rest).
  const double invariant = 3.0 + std::max(shift, 0.0);
  const double argument =
      std::clamp(-3.0 * std::sqrt(3.0) / (invariant * std::sqrt(invariant)), -1.0, 1.0);
  return 2.0 * std::sqrt(invariant / 3.0) * std::cos(std::acos(argument) / 3.0);
}

IsochoricPeak isochoricPeak(double shift) {
  IsochoricPeak peak;
  peak.shift = std::max(shift, 0.0);
  peak.inverseMeasure = 1.0 / measureOfShift(peak.shift).value;
  return peak;
}

IsochoricPeak isochoricPeak(const StrainEnergy& energy, const StressSoftening& softening,
                            double shift) {
  IsochoricPeak peak = isochoricPeak(shift);
  peak.energy_Pa = energy.atInvariantShift(peak.shift).energy;
  // q = (1 - m / M) m falls as m rises from sqrt 3 (rest) to M, reaching q_0 at the larger root
  // of m^2 - M m + M q_0 = 0; the stretch there is the root of u^3 - m^2 u + 2 = 0, u = lambda^2
  // (uniaxialStretchOfShift's cubic at I = m^2).
  const double measure = 1.0 / peak.inverseMeasure;
  const double q0 = softening.onsetMeasure();
  const double restMeasure = std::sqrt(3.0);
  if ((1.0 - restMeasure * peak.inverseMeasure) * restMeasure <= q0) return peak;  // all onset
  const double onsetMeasure =
      0.5 * (measure + std::sqrt(std::max(0.0, measure * measure - 4.0 * measure * q0)));
  const double u = uniaxialStretchOfShift(onsetMeasure * onsetMeasure - 3.0);
  peak.onsetShift = std::clamp(u + 2.0 / std::sqrt(u) - 3.0, 0.0, peak.shift);
  return peak;
}

double isochoricSofteningFactor(const StressSoftening& softening, double shift,
                                const IsochoricPeak& peak) {
  return isochoricSofteningFactorWithSlope(softening, shift, peak).value;
}

IsochoricSofteningFactor isochoricSofteningFactorWithSlope(const StressSoftening& softening,
                                                           double shift,
                                                           const IsochoricPeak& peak) {
  if (!(shift < peak.shift)) return {};
  const Measure m = measureOfShift(shift);
  const double q = std::max(0.0, (1.0 - m.value * peak.inverseMeasure) * m.value);
  const StressSoftening::RootOfMeasure root = softening.rootOfMeasure<true>(q);
  const double factor = std::exp(-softening.b() * root.value);
  // dq/dI = (1 - 2 m / M) dm/dI.
  const double measureSlope = (1.0 - 2.0 * m.value * peak.inverseMeasure) * m.slope;
  return {factor, -softening.b() * factor * root.slope * measureSlope};
}

EnergyInI1 softenedIsochoricEnergy(const StrainEnergy& energy, const StressSoftening& softening,
                                   double shift, const IsochoricPeak& peak,
                                   const EnergyInI1& virgin) {
  if (!(shift < peak.shift)) return virgin;
  const IsochoricSofteningFactor factor = isochoricSofteningFactorWithSlope(softening, shift, peak);
  EnergyInI1 softened;
  softened.dEnergy = factor.value * virgin.dEnergy;
  softened.d2Energy = factor.value * virgin.d2Energy + factor.slope * virgin.dEnergy;
  softened.energy = peak.energy_Pa - softenedWork(energy, softening, peak, shift, peak.shift);
  return softened;
}

}  // namespace tissuesim
