// SPDX-License-Identifier: Apache-2.0
#include "material/InverseLangevin.h"

#include <cmath>

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

TEST(InverseLangevin, ExactInverseRoundTrips) {
  for (double r = 0.001; r < 0.9995; r += 0.0137) {
    const double beta = inverseLangevinExact(r).beta;
    EXPECT_NEAR(langevin(beta), r, 1e-14 * std::max(1.0, r)) << "r = " << r;
  }
}

TEST(InverseLangevin, LangevinSeriesJoinsClosedFormSmoothly) {
  // Either side of the switch to the series the values agree to double precision.
  for (const double beta : {0.0099, 0.01, 0.0101}) {
    const double closed = 1.0 / std::tanh(beta) - 1.0 / beta;
    EXPECT_NEAR(langevin(beta), closed, 1e-12);
  }
  EXPECT_DOUBLE_EQ(langevin(0.0), 0.0);
  EXPECT_NEAR(langevinSlope(0.0), 1.0 / 3.0, 1e-15);
}

TEST(InverseLangevin, PusoIsWithinAFewPercentOfExact) {
  for (double r = 0.05; r < 0.999; r += 0.01) {
    const double exact = inverseLangevinExact(r).beta;
    const double puso = inverseLangevinPuso(r).beta;
    EXPECT_LT(std::abs(puso - exact) / exact, 0.05) << "r = " << r;
  }
}

TEST(InverseLangevin, DerivativesMatchFiniteDifferences) {
  const double h = 1e-6;
  for (double r = 0.1; r < 0.99; r += 0.07) {
    for (const auto& inverse : {&inverseLangevinPuso, &inverseLangevinExact}) {
      const InverseLangevinValue centre = inverse(r);
      const InverseLangevinValue up = inverse(r + h);
      const InverseLangevinValue down = inverse(r - h);
      EXPECT_NEAR(centre.dBeta, (up.beta - down.beta) / (2 * h), 1e-6 * std::abs(centre.dBeta));
      EXPECT_NEAR(centre.d2Beta, (up.dBeta - down.dBeta) / (2 * h),
                  1e-5 * std::abs(centre.d2Beta) + 1e-6);
    }
  }
}

TEST(InverseLangevin, LogSinhDoesNotOverflow) {
  EXPECT_NEAR(logSinh(1.0), std::log(std::sinh(1.0)), 1e-14);
  EXPECT_TRUE(std::isfinite(logSinh(5000.0)));
  EXPECT_NEAR(logSinh(5000.0), 5000.0 - std::log(2.0), 1e-9);
}

}  // namespace
}  // namespace tissuesim
