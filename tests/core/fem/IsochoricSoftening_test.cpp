// SPDX-License-Identifier: Apache-2.0
// Softening at the FEM's material points: the equivalent uniaxial stretch inverts I1bar, and the
// factor is the spring law's for that stretch below the peak and 1 at or past it.

#include "fem/IsochoricSoftening.h"

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

}  // namespace
}  // namespace tissuesim
