// SPDX-License-Identifier: Apache-2.0
#include "material/StressSoftening.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "material/StrainEnergy.h"
#include "support/TestTissues.h"

namespace tissuesim {
namespace {

class StressSofteningTest : public ::testing::Test {
 protected:
  TissueParameters m_parameters = test::porcineLiver();
  StrainEnergy m_energy{m_parameters};
  StressSoftening m_softening{m_parameters};

  double softened(double lambda, double lambdaMax) const {
    return m_softening.soften(m_energy.stress(lambda), lambda, lambdaMax);
  }
};

TEST_F(StressSofteningTest, MonotonicLoadingFollowsTheVirginCurve) {
  MullinsState state;
  for (double lambda = 1.0; lambda <= 1.3; lambda += 0.01) {
    EXPECT_EQ(m_softening.soften(m_energy.stress(lambda), lambda, state.lambdaMax()),
              m_energy.stress(lambda));
    state.observe(lambda);
  }
}

TEST_F(StressSofteningTest, FactorIsOneAtLambdaMaxAndBelowOneUnderIt) {
  EXPECT_DOUBLE_EQ(m_softening.factor(1.23, 1.23), 1.0);
  double previous = 1.0;
  for (double lambda = 1.22; lambda > 1.0; lambda -= 0.02) {
    const double factor = m_softening.factor(lambda, 1.23);
    EXPECT_LT(factor, previous) << lambda;  // more softening the further below lambda_max
    EXPECT_GT(factor, 0.0);
    previous = factor;
  }
}

TEST_F(StressSofteningTest, UnloadingLiesBelowTheVirginCurve) {
  for (const double peak : {1.15, 1.23, 1.30}) {
    for (double lambda = 1.01; lambda < peak - 1e-3; lambda += 0.005) {
      EXPECT_LT(softened(lambda, peak), m_energy.stress(lambda)) << lambda << " from " << peak;
    }
  }
}

TEST_F(StressSofteningTest, UnloadingReachesZeroStressAtASmallResidualStretch) {
  for (const double peak : {1.15, 1.23, 1.30}) {
    EXPECT_LT(softened(1.0, peak), 0.0) << "permanent set: compressive stress at lambda = 1";
    EXPECT_GT(softened(peak - 1e-3, peak), 0.0);
    // Bisection for the zero crossing: the residual stretch.
    double lo = 1.0;
    double hi = peak - 1e-3;
    for (int k = 0; k < 60; ++k) {
      const double mid = 0.5 * (lo + hi);
      (softened(mid, peak) < 0.0 ? lo : hi) = mid;
    }
    EXPECT_GT(lo, 1.0);
    EXPECT_LT(lo, 1.0 + 0.25 * (peak - 1.0)) << "residual stretch should be small";
  }
}

TEST_F(StressSofteningTest, ReloadingPastLambdaMaxRejoinsTheVirginCurve) {
  MullinsState state;
  state.observe(1.15);
  EXPECT_LT(softened(1.10, state.lambdaMax()), m_energy.stress(1.10));
  EXPECT_EQ(m_softening.soften(m_energy.stress(1.20), 1.20, state.lambdaMax()),
            m_energy.stress(1.20));
}

TEST_F(StressSofteningTest, LambdaMaxNeverDecreasesUntilReset) {
  MullinsState state;
  EXPECT_EQ(state.lambdaMax(), 1.0);
  state.observe(1.2);
  state.observe(1.1);
  state.observe(0.8);
  EXPECT_EQ(state.lambdaMax(), 1.2);
  state.observe(1.25);
  EXPECT_EQ(state.lambdaMax(), 1.25);
  state.reset();
  EXPECT_EQ(state.lambdaMax(), 1.0);
}

TEST_F(StressSofteningTest, ExponentTwoRemovesTheJumpAtLambdaMax) {
  // n = 1: the softened curve starts a hair above the virgin one (model.md); n = 2: no jump.
  const double peak = 1.23;
  const double below = peak - 1e-14;  // the factor's vertical tangent: stay very close
  EXPECT_GT(softened(below, peak), m_energy.stress(peak));
  TissueParameters p = m_parameters;
  p.softeningExponentN = 2;
  const StressSoftening squared(p);
  // n = 1 jumps by 1.4e-4 relative here; n = 2 must stay 10x closer than that.
  EXPECT_NEAR(squared.soften(m_energy.stress(below), below, peak), m_energy.stress(peak),
              1e-5 * m_energy.stress(peak));
}

TEST_F(StressSofteningTest, CompressionAfterStretchingIsContinuousAtRest) {
  const double peak = 1.2;
  // The virgin slope is 3 mu0 = 5.6 kPa per unit stretch: 1e-9 below rest moves 6e-6 Pa.
  EXPECT_NEAR(softened(1.0 - 1e-9, peak), softened(1.0, peak), 1e-4);
  EXPECT_LT(softened(0.9, peak), softened(1.0, peak));
  // Never stretched: compression is virgin.
  EXPECT_EQ(m_softening.soften(m_energy.stress(0.9), 0.9, 1.0), m_energy.stress(0.9));
}

// q = (1 - m / M) m of Eq. 20, the measure whose square root F takes.
double measureGap(double lambda, double lambdaMax) {
  const auto m = [](double l) { return std::sqrt(l * l * l * l + 2.0 / (l * l)); };
  return (1.0 - m(lambda) / m(lambdaMax)) * m(lambda);
}

TEST_F(StressSofteningTest, TheRoundedOnsetIsTheExactLawPastItAndWithinItsBoundInside) {
  // Below q_0 sqrt(q) becomes sqrt(q_0) t (3 - t) / 2: never above it, so the stress is never
  // below the exact law's there, and at most exp(0.1741 b sqrt(q_0)) - 1 above it (the largest
  // of sqrt(t) - t (3 - t) / 2 on [0, 1] is 0.17404).
  constexpr double kOnset = 1e-4;
  const StressSoftening rounded(m_parameters, kOnset);
  const double bound = std::exp(0.1741 * m_parameters.softeningB * std::sqrt(kOnset)) - 1.0;
  for (const double peak : {1.01, 1.1, 1.2, 1.3}) {
    int inside = 0;
    double largest = 0.0;
    for (double below = 1e-9; below < 0.02; below *= 1.05) {
      const double lambda = peak - below;
      const double exact = softened(lambda, peak);
      const double smooth = rounded.soften(m_energy.stress(lambda), lambda, peak);
      if (measureGap(lambda, peak) >= kOnset) {
        EXPECT_DOUBLE_EQ(smooth, exact) << lambda << " from " << peak;
        continue;
      }
      ++inside;
      const double ratio = smooth / exact - 1.0;
      EXPECT_GE(ratio, -1e-14) << lambda << " from " << peak;
      EXPECT_LE(ratio, bound) << lambda << " from " << peak;
      largest = std::max(largest, ratio);
    }
    EXPECT_GT(inside, 50) << peak;
    EXPECT_GT(largest, 0.5 * bound) << "the onset changed the curve inside it: " << peak;
  }
  EXPECT_DOUBLE_EQ(rounded.factor(1.2, 1.2), 1.0);
  EXPECT_EQ(rounded.soften(m_energy.stress(1.25), 1.25, 1.2), m_energy.stress(1.25));
}

TEST_F(StressSofteningTest, TheRoundedOnsetHasAFiniteTangentAtThePeakAndItIsTheDerivative) {
  // The exact law's tangent is vertical at lambda_max (capped where sqrt(q) = 1e-6); the rounded
  // one's is 3 b q'(lambda) / (2 sqrt(q_0)) times the stress there, and its slopes are the
  // derivative of its values inside the onset, across q_0 and past it.
  constexpr double kOnset = 1e-4;
  const StressSoftening rounded(m_parameters, kOnset);
  const double peak = 1.2;
  const auto slopeAt = [&](const StressSoftening& law, double lambda) {
    return law.softenWithSlope(m_energy.stressAndSlope(lambda), lambda, peak).slope;
  };
  const double justBelow = peak - 1e-12;
  const double stress = m_energy.stress(peak);
  // dq/dlambda at the peak (negative: q grows going down from it).
  const double measureSlope =
      (measureGap(peak - 1e-6, peak) - measureGap(peak - 2e-6, peak)) / 1e-6;
  const double expected =
      1.5 * m_parameters.softeningB * -measureSlope / std::sqrt(kOnset) * stress;
  EXPECT_NEAR(slopeAt(rounded, justBelow), expected + m_energy.stressAndSlope(peak).slope,
              0.01 * expected);
  EXPECT_GT(slopeAt(m_softening, justBelow), 1000.0 * expected) << "the exact law's, capped";
  for (double below = 1e-6; below < 0.01; below *= 1.7) {
    const double lambda = peak - below;
    const double h = 1e-9;
    const double fd = (rounded.soften(m_energy.stress(lambda + h), lambda + h, peak) -
                       rounded.soften(m_energy.stress(lambda - h), lambda - h, peak)) /
                      (2.0 * h);
    EXPECT_NEAR(slopeAt(rounded, lambda), fd, 1e-4 * std::abs(fd)) << lambda;
  }
}

TEST_F(StressSofteningTest, ResidualTermMatchesEq17ByHand) {
  // lambda_1 g_1 - lambda_3 g_3 with n = 1 at lambda = 1.1 from lambda_max = 1.2.
  const double l = 1.1;
  const double lm = 1.2;
  const double bracket = -4 * l * l * (lm - l * l) + 4 / l * (1 / std::sqrt(lm) - 1 / l);
  const double expected = m_parameters.mu_Pa / (2 * m_parameters.softeningC_Pa) * bracket * 1000;
  EXPECT_NEAR(m_softening.residualStress(l, lm), expected, 1e-12 * std::abs(expected));
}

}  // namespace
}  // namespace tissuesim
