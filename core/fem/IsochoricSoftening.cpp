// SPDX-License-Identifier: Apache-2.0
#include "fem/IsochoricSoftening.h"

#include <algorithm>
#include <cmath>

namespace tissuesim {
namespace {

/// m = sqrt(lambda^4 + 2 lambda^-2) (Eq. 20) at I1bar - 3 = shift.
double measureOfShift(double shift) {
  const double lambda = uniaxialStretchOfShift(shift);
  const double inverse = 1.0 / lambda;
  return std::sqrt(lambda * lambda * lambda * lambda + 2.0 * inverse * inverse);
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
  peak.inverseMeasure = 1.0 / measureOfShift(peak.shift);
  return peak;
}

double isochoricSofteningFactor(const StressSoftening& softening, double shift,
                                const IsochoricPeak& peak) {
  if (!(shift < peak.shift)) return 1.0;
  const double m = measureOfShift(shift);
  const double q = std::max(0.0, (1.0 - m * peak.inverseMeasure) * m);
  return std::exp(-softening.b() * softening.rootOfMeasure<false>(q).value);
}

}  // namespace tissuesim
