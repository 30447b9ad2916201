// SPDX-License-Identifier: Apache-2.0
#include "springs/SpringForceLaw.h"

#include <cmath>

#include <gtest/gtest.h>

#include "support/TestSystems.h"

namespace tissuesim {
namespace {

const test::LiverMaterial& liverMaterial() { return test::LiverMaterial::instance(); }

TEST(SpringForceLaw, EesmIsTheTableStress) {
  const SpringForceLaw law(SpringLaw::Eesm, liverMaterial().table, liverMaterial().parameters, 0.0,
                           false);
  for (const double lambda : {0.7, 0.95, 1.0, 1.1, 1.4}) {
    const SpringStress p = law.evaluate(lambda, 1.0);
    EXPECT_DOUBLE_EQ(p.stress, liverMaterial().table.stress(lambda));
    EXPECT_FALSE(p.isBeyondRange);
  }
}

TEST(SpringForceLaw, PaperLawIsTheSecantForceOverArea) {
  const SpringForceLaw law(SpringLaw::EesmPaper, liverMaterial().table, liverMaterial().parameters,
                           0.0, false);
  const double lambda = 1.2;
  EXPECT_NEAR(law.evaluate(lambda, 1.0).stress,
              liverMaterial().table.springStiffness(lambda) * lambda /
                  liverMaterial().parameters.springArea_m2,
              1e-9);
}

TEST(SpringForceLaw, SlopesMatchFiniteDifferences) {
  for (const SpringLaw kind : {SpringLaw::Eesm, SpringLaw::EesmPaper, SpringLaw::Smm}) {
    for (const bool isSoftening : {false, true}) {
      const SpringForceLaw law(kind, liverMaterial().table, liverMaterial().parameters, 5000.0,
                               isSoftening);
      const double lambdaMax = 1.25;
      for (const double lambda : {0.8, 0.97, 1.03, 1.1, 1.2, 1.3, 1.45}) {
        const double h = 1e-7;
        const double fd = (law.evaluate(lambda + h, lambdaMax).stress -
                           law.evaluate(lambda - h, lambdaMax).stress) /
                          (2 * h);
        const double slope = law.evaluate(lambda, lambdaMax).slope;
        EXPECT_NEAR(slope, fd, 1e-5 * std::abs(fd) + 1e-3)
            << "law " << static_cast<int>(kind) << " softening " << isSoftening << " at " << lambda;
      }
    }
  }
}

TEST(SpringForceLaw, BeyondLockingTheBarrierContinuesLinearlyAndSaysSo) {
  const SpringForceLaw law(SpringLaw::Eesm, liverMaterial().table, liverMaterial().parameters, 0.0,
                           false);
  const StretchRange range = law.range();
  const SpringStress end = law.evaluate(range.upper, 1.0);
  const SpringStress past = law.evaluate(range.upper + 0.1, 1.0);
  EXPECT_TRUE(past.isBeyondRange);
  EXPECT_TRUE(std::isfinite(past.stress));
  EXPECT_NEAR(past.stress, end.stress + 0.1 * end.slope, 1e-9 * std::abs(past.stress));
  EXPECT_GT(past.stress, end.stress);  // it keeps resisting
  const SpringStress crushed = law.evaluate(0.1, 1.0);
  EXPECT_TRUE(crushed.isBeyondRange);
  EXPECT_LT(crushed.stress, law.evaluate(range.lower, 1.0).stress);
}

TEST(SpringForceLaw, SofteningAppliesBelowLambdaMaxOnly) {
  const SpringForceLaw law(SpringLaw::Eesm, liverMaterial().table, liverMaterial().parameters, 0.0,
                           true);
  EXPECT_TRUE(law.isSoftening());
  EXPECT_LT(law.evaluate(1.1, 1.2).stress, liverMaterial().table.stress(1.1));
  EXPECT_DOUBLE_EQ(law.evaluate(1.25, 1.2).stress, liverMaterial().table.stress(1.25));
  const SpringForceLaw linear(SpringLaw::Smm, liverMaterial().table, liverMaterial().parameters,
                              5000.0, true);
  EXPECT_FALSE(linear.isSoftening());
  EXPECT_NEAR(linear.evaluate(1.1, 1.2).stress, 500.0, 1e-9);
}

}  // namespace
}  // namespace tissuesim
