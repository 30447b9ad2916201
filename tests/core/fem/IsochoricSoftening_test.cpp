// SPDX-License-Identifier: Apache-2.0
// Softening at the FEM's material points: the equivalent uniaxial stretch inverts I1bar, and the
// factor is the spring law's for that stretch below the peak and 1 at or past it.

#include "fem/IsochoricSoftening.h"

#include <algorithm>

#include <gtest/gtest.h>

#include "support/TestSystems.h"

namespace tissuesim {
namespace {

double shiftOfStretch(double lambda) { return lambda * lambda + 2.0 / lambda - 3.0; }

TEST(IsochoricSoftening, TheEquivalentStretchInvertsTheInvariant) {
  EXPECT_DOUBLE_EQ(uniaxialStretchOfShift(0.0), 1.0);
  for (const double lambda : {1.0001, 1.01, 1.1, 1.3, 1.6})
    EXPECT_NEAR(uniaxialStretchOfShift(shiftOfStretch(lambda)), lambda, 1e-9 * lambda) << lambda;
}

TEST(IsochoricSoftening, TheFactorIsTheSpringLawsAtTheSameStretch) {
  const StressSoftening& softening = test::liverSoftening();
  ASSERT_GT(softening.b(), 0.0);
  const IsochoricPeak peak = isochoricPeak(shiftOfStretch(1.3));
  for (const double lambda : {1.0, 1.1, 1.2, 1.29, 1.2999}) {
    const double expected = softening.factor(lambda, 1.3);
    ASSERT_LT(expected, 0.999) << lambda;  // softened: the comparison can fail
    EXPECT_NEAR(isochoricSofteningFactor(softening, shiftOfStretch(lambda), peak), expected, 1e-9)
        << lambda;
  }
  // At and past the peak, and never strained: the virgin curve.
  EXPECT_EQ(isochoricSofteningFactor(softening, peak.shift, peak), 1.0);
  EXPECT_EQ(isochoricSofteningFactor(softening, peak.shift + 0.1, peak), 1.0);
  EXPECT_EQ(isochoricSofteningFactor(softening, 0.1, IsochoricPeak{}), 1.0);
}

TEST(IsochoricSoftening, TheFactorsSlopeIsItsDerivative) {
  // Below the rounded onset, within it, and near rest, where the stretch has no slope in I.
  const StressSoftening& softening = test::liverSoftening();
  const IsochoricPeak peak = isochoricPeak(test::liverEnergy(), softening, shiftOfStretch(1.3));
  ASSERT_GT(peak.onsetShift, shiftOfStretch(1.29));
  ASSERT_LT(peak.onsetShift, peak.shift);
  const double inOnset = 0.5 * (peak.onsetShift + peak.shift);
  for (const double shift : {1e-3, shiftOfStretch(1.1), shiftOfStretch(1.29), inOnset}) {
    const double step = 1e-6 * std::min(shift, peak.shift - shift);
    const double expected = (isochoricSofteningFactor(softening, shift + step, peak) -
                             isochoricSofteningFactor(softening, shift - step, peak)) /
                            (2.0 * step);
    const IsochoricSofteningFactor factor =
        isochoricSofteningFactorWithSlope(softening, shift, peak);
    ASSERT_GT(expected, 0.0) << shift;  // F rises to the peak: the comparison can fail
    EXPECT_NEAR(factor.slope, expected, 1e-5 * expected) << shift;
  }
  EXPECT_EQ(isochoricSofteningFactorWithSlope(softening, peak.shift, peak).slope, 0.0);
}

TEST(IsochoricSoftening, TheSoftenedEnergysSlopesAreItsDerivativesAndItMeetsTheVirginAtThePeak) {
  // W_s' = F W_T' is W_s's derivative (its integral taken by quadrature), and W_s'' W_s''s, on
  // both sides of the onset and near rest; at the peak W_s is W_T, and past it W_T itself.
  const StrainEnergy& energy = test::liverEnergy();
  const StressSoftening& softening = test::liverSoftening();
  const IsochoricPeak peak = isochoricPeak(energy, softening, shiftOfStretch(1.3));
  const auto softened = [&](double shift) {
    return softenedIsochoricEnergy(energy, softening, shift, peak, energy.atInvariantShift(shift));
  };
  const double inOnset = 0.5 * (peak.onsetShift + peak.shift);
  for (const double shift : {1e-3, shiftOfStretch(1.1), shiftOfStretch(1.25), inOnset}) {
    const double step = 1e-4 * std::min(shift, peak.shift - shift);
    const EnergyInI1 at = softened(shift);
    const EnergyInI1 above = softened(shift + step);
    const EnergyInI1 below = softened(shift - step);
    EXPECT_NEAR(
        at.dEnergy,
        isochoricSofteningFactor(softening, shift, peak) * energy.atInvariantShift(shift).dEnergy,
        1e-12 * at.dEnergy);
    ASSERT_LT(at.dEnergy, 0.99 * energy.atInvariantShift(shift).dEnergy) << shift;  // softened
    // To the quadrature's accuracy (a line search needs the energy to agree with its slope to
    // far less): about 1e-6 near rest, where the stretch's own root is steep.
    EXPECT_NEAR((above.energy - below.energy) / (2.0 * step), at.dEnergy, 1e-5 * at.dEnergy)
        << shift;
    EXPECT_NEAR((above.dEnergy - below.dEnergy) / (2.0 * step), at.d2Energy, 1e-5 * at.d2Energy)
        << shift;
    EXPECT_GT(at.d2Energy, 0.0) << shift;
  }
  const EnergyInI1 virginAtPeak = energy.atInvariantShift(peak.shift);
  const double justBelow = peak.shift * (1.0 - 1e-9);
  EXPECT_NEAR(softened(justBelow).energy, virginAtPeak.energy, 1e-6 * virginAtPeak.energy);
  EXPECT_NEAR(softened(justBelow).dEnergy, virginAtPeak.dEnergy, 1e-6 * virginAtPeak.dEnergy);
  const double past = peak.shift + 0.1;
  EXPECT_EQ(softened(past).energy, energy.atInvariantShift(past).energy);
  EXPECT_EQ(softened(past).d2Energy, energy.atInvariantShift(past).d2Energy);
  // Less work is given back on unloading than the loading took: the energy left at rest is what
  // the softening dissipated.
  EXPECT_GT(softened(0.0).energy, 0.1 * virginAtPeak.energy);
  EXPECT_LT(softened(0.0).energy, virginAtPeak.energy);
}

}  // namespace
}  // namespace tissuesim
