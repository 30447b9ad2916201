// SPDX-License-Identifier: Apache-2.0
#include "material/StrainEnergy.h"

#include <cmath>

#include <gtest/gtest.h>

#include "support/TestTissues.h"

namespace tissuesim {
namespace {

class StrainEnergyTest : public ::testing::TestWithParam<InverseLangevin> {
 protected:
  TissueParameters parameters() const {
    TissueParameters p = test::porcineLiver();
    p.inverseLangevin = GetParam();
    return p;
  }
};

TEST_P(StrainEnergyTest, EnergyAndStressVanishAtRest) {
  const StrainEnergy energy(parameters());
  EXPECT_DOUBLE_EQ(energy.energy(1.0), 0.0);
  EXPECT_DOUBLE_EQ(energy.stress(1.0), 0.0);
}

TEST_P(StrainEnergyTest, StressIsTheDerivativeOfEnergy) {
  const StrainEnergy energy(parameters());
  const StretchRange usable = energy.usableRange();
  // Fourth-order central differences, steps well inside the distance to locking.
  for (double lambda = usable.lower + 0.01; lambda < usable.upper - 0.01; lambda += 0.0173) {
    const double h = 1e-4;
    const double fd = (-energy.energy(lambda + 2 * h) + 8 * energy.energy(lambda + h) -
                       8 * energy.energy(lambda - h) + energy.energy(lambda - 2 * h)) /
                      (12 * h);
    const UniaxialResponse w = energy.uniaxial(lambda);
    EXPECT_NEAR(w.stress, fd, 1e-7 * std::abs(w.stress) + 1e-6) << "lambda = " << lambda;
    const double fdSlope = (-energy.stress(lambda + 2 * h) + 8 * energy.stress(lambda + h) -
                            8 * energy.stress(lambda - h) + energy.stress(lambda - 2 * h)) /
                           (12 * h);
    EXPECT_NEAR(w.stressSlope, fdSlope, 1e-6 * std::abs(w.stressSlope) + 1e-6)
        << "lambda = " << lambda;
  }
}

TEST_P(StrainEnergyTest, EnergyIsPositiveAwayFromRestAndStressHasTheSignOfStrain) {
  const StrainEnergy energy(parameters());
  for (const double lambda : {0.7, 0.9, 0.99, 1.01, 1.1, 1.3, 1.45}) {
    EXPECT_GT(energy.energy(lambda), 0.0) << lambda;
    EXPECT_EQ(energy.stress(lambda) > 0.0, lambda > 1.0) << lambda;
  }
}

TEST_P(StrainEnergyTest, SmallStrainLimitIsLinearWithYoungsModulusThreeMu0) {
  const StrainEnergy energy(parameters());
  const double mu0 = energy.initialShearModulus();
  ASSERT_GT(mu0, 0.0);
  // Series about rest (model.md):
  //   W = 3/2 mu0 e^2 - mu0 e^3 + O(e^4),  P = 3 mu0 e - 3 mu0 e^2 + O(e^3).
  // The liver's large A2 makes the next terms about 1500 e^2 relative: keep e small.
  for (const double e : {2e-5, -2e-5, 1e-6, -1e-7}) {
    EXPECT_NEAR(energy.stress(1.0 + e), 3.0 * mu0 * (e - e * e), 1e-5 * std::abs(3.0 * mu0 * e));
    EXPECT_NEAR(energy.energy(1.0 + e), mu0 * (1.5 * e * e - e * e * e), 1e-5 * 1.5 * mu0 * e * e);
  }
}

INSTANTIATE_TEST_SUITE_P(BothInverses, StrainEnergyTest,
                         ::testing::Values(InverseLangevin::Puso, InverseLangevin::Exact),
                         [](const ::testing::TestParamInfo<InverseLangevin>& inverse) {
                           return inverse.param == InverseLangevin::Puso ? "Puso" : "Exact";
                         });

TEST(StrainEnergy, LockingRangeOfThePorcineLiver) {
  const StrainEnergy energy(test::porcineLiver());
  const StretchRange locking = energy.lockingRange();
  // model.md: about 0.62 < lambda < 1.50.
  EXPECT_NEAR(locking.lower, 0.62, 0.01);
  EXPECT_NEAR(locking.upper, 1.50, 0.01);
  const double n = energy.parameters().chainSegmentsN;
  for (const double lambda : {locking.lower, locking.upper}) {
    EXPECT_NEAR(lambda * lambda * lambda - 3 * n * lambda + 2, 0.0, 1e-13);
    // r = sqrt(I1 / 3N) = 1 there
    EXPECT_NEAR(StrainEnergy::firstInvariant(lambda) / (3 * n), 1.0, 1e-13);
  }
  const StretchRange usable = energy.usableRange();
  EXPECT_GT(usable.lower, locking.lower);
  EXPECT_LT(usable.upper, locking.upper);
  EXPECT_NEAR(std::sqrt(StrainEnergy::firstInvariant(usable.upper) / (3 * n)),
              1.0 - StrainEnergy::kLockingMargin, 1e-12);
  EXPECT_TRUE(std::isfinite(energy.stress(usable.upper)));
  EXPECT_TRUE(std::isfinite(energy.stress(usable.lower)));
}

TEST(StrainEnergy, LockingRangeFollowsN) {
  TissueParameters p = test::porcineLiver();
  p.chainSegmentsN = 3.0;
  const StretchRange wide = StrainEnergy(p).lockingRange();
  p.chainSegmentsN = 1.01;
  const StretchRange narrow = StrainEnergy(p).lockingRange();
  EXPECT_GT(wide.upper, narrow.upper);
  EXPECT_LT(wide.lower, narrow.lower);
  EXPECT_LT(narrow.lower, 1.0);
  EXPECT_GT(narrow.upper, 1.0);
}

TEST(StrainEnergy, ExactInverseMatchesThePapersResponseFunctionEq15) {
  // With f = 0, 2 dW_T/dI1 is the network response function N of Eq. 15 (exact inverse only).
  TissueParameters p = test::porcineLiver();
  p.fibreFraction = 0.0;
  p.inverseLangevin = InverseLangevin::Exact;
  const StrainEnergy energy(p);
  const double n = p.chainSegmentsN;
  for (const double lambda : {0.8, 1.05, 1.2, 1.35}) {
    const double i1 = StrainEnergy::firstInvariant(lambda);
    const double r = std::sqrt(i1 / (3 * n));
    // beta from bisection on the Langevin function, independent of the code under test
    double lo = 1e-9;
    double hi = 1e6;
    for (int k = 0; k < 200; ++k) {
      const double mid = 0.5 * (lo + hi);
      (1.0 / std::tanh(mid) - 1.0 / mid < r ? lo : hi) = mid;
    }
    const double beta = 0.5 * (lo + hi);
    const double responseEq15 =
        p.mu_Pa / (3 * r) * (beta + 1 / n * (1 / r - 1 / (beta * (1 - r * r - 2 * r / beta))));
    EXPECT_NEAR(2 * energy.inI1(i1).dEnergy, responseEq15, 1e-9 * responseEq15) << lambda;
  }
}

}  // namespace
}  // namespace tissuesim
