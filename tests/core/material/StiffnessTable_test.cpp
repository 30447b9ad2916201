// SPDX-License-Identifier: Apache-2.0
#include "material/StiffnessTable.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "support/TestTissues.h"

namespace tissuesim {
namespace {

class StiffnessTableTest : public ::testing::TestWithParam<InverseLangevin> {
 protected:
  static TissueParameters parameters() {
    TissueParameters p = test::porcineLiver();
    p.inverseLangevin = GetParam();
    return p;
  }
  StrainEnergy m_energy{parameters()};
  StiffnessTable m_table{m_energy};
};

TEST_P(StiffnessTableTest, CoversTheUsableRangeInsideLocking) {
  const StretchRange range = m_table.range();
  EXPECT_GE(range.lower, m_energy.usableRange().lower);
  EXPECT_LE(range.upper, m_energy.usableRange().upper);
  EXPECT_LT(range.upper - m_energy.usableRange().upper, 1e-9);
  EXPECT_LT(m_energy.usableRange().upper - range.upper, m_table.spacing() + 1e-12);
  EXPECT_GT(m_table.nodeCount(), 100u);
}

TEST_P(StiffnessTableTest, LookupsMatchTheClosedFormToOnePartPerMillion) {
  const StretchRange range = m_table.range();
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> uniform(range.lower, range.upper);
  double worstStress = 0.0;
  double worstStiffness = 0.0;
  double worstEnergy = 0.0;
  auto check = [&](double lambda) {
    if (lambda == 1.0) return;
    const UniaxialResponse exact = m_energy.uniaxial(lambda);
    const double exactStiffness = StiffnessTable::closedFormStiffness(m_energy, lambda).value;
    worstStress = std::max(
        worstStress, std::abs(m_table.stress(lambda) - exact.stress) / std::abs(exact.stress));
    worstStiffness =
        std::max(worstStiffness, std::abs(m_table.springStiffness(lambda) - exactStiffness) /
                                     std::abs(exactStiffness));
    worstEnergy =
        std::max(worstEnergy, std::abs(m_table.energy(lambda) - exact.energy) / exact.energy);
  };
  for (int i = 0; i < 20000; ++i) check(uniform(random));
  // The hard places: next to rest (values through zero) and next to the table ends (poles).
  for (double d = 1e-7; d < 0.05; d *= 1.7) {
    check(1.0 + d);
    check(1.0 - d);
    check(range.upper - d);
    check(range.lower + d);
  }
  EXPECT_LT(worstStress, 1e-6);
  EXPECT_LT(worstStiffness, 1e-6);
  EXPECT_LT(worstEnergy, 1e-6);
}

TEST_P(StiffnessTableTest, StressSlopeIsConsistentWithTheStress) {
  for (double lambda = 0.7; lambda < 1.45; lambda += 0.0311) {
    const HermiteNode node = m_table.stressAndSlope(lambda);
    EXPECT_DOUBLE_EQ(node.value, m_table.stress(lambda));
    const double exactSlope = m_energy.uniaxial(lambda).stressSlope;
    EXPECT_NEAR(node.slope, exactSlope, 1e-5 * std::abs(exactSlope)) << lambda;
  }
}

INSTANTIATE_TEST_SUITE_P(BothInverses, StiffnessTableTest,
                         ::testing::Values(InverseLangevin::Puso, InverseLangevin::Exact),
                         [](const ::testing::TestParamInfo<InverseLangevin>& inverse) {
                           return inverse.param == InverseLangevin::Puso ? "Puso" : "Exact";
                         });

TEST(StiffnessTable, StiffnessIsFiniteAndSmoothThroughRestAndMatchesItsSeries) {
  const StrainEnergy energy(test::porcineLiver());
  const StiffnessTable table(energy);
  const double area = energy.parameters().springArea_m2;
  const double mu0 = energy.initialShearModulus();
  EXPECT_EQ(StiffnessTable::closedFormStiffness(energy, 1.0).value, 0.0);
  EXPECT_NEAR(table.springStiffness(1.0), 0.0, 1e-12 * area * mu0);
  // k_s = v (3 mu0 e - 5 mu0 e^2 + O(e^3)); the liver's e^3 term is about 750 e^2 relative.
  for (const double e : {1e-10, -1e-10, 1e-8, -1e-8, 1e-6, -1e-6, 1e-5, -1e-5}) {
    const double series = area * mu0 * (3 * e - 5 * e * e);
    const HermiteNode closed = StiffnessTable::closedFormStiffness(energy, 1.0 + e);
    ASSERT_TRUE(std::isfinite(closed.value));
    EXPECT_NEAR(closed.value, series, 1e-6 * std::abs(series)) << e;
    EXPECT_NEAR(table.springStiffness(1.0 + e), series, 1e-6 * std::abs(series)) << e;
    EXPECT_NEAR(closed.slope, 3 * area * mu0, 1e-3 * 3 * area * mu0) << e;
  }
  // In compression W_T > 0 but k_s < 0 (model.md).
  EXPECT_LT(table.springStiffness(0.9), 0.0);
  EXPECT_GT(table.springStiffness(1.1), 0.0);
}

TEST(StiffnessTable, ClosedFormIsContinuousWhereQuadratureHandsOverToDivision) {
  const StrainEnergy energy(test::porcineLiver());
  // I1 - 3 = 1e-2 near lambda = 1 +- 0.058: scan across it on both sides.
  for (double lambda = 0.93; lambda < 1.07; lambda += 1e-4) {
    const HermiteNode a = StiffnessTable::closedFormStiffness(energy, lambda);
    const HermiteNode b = StiffnessTable::closedFormStiffness(energy, lambda + 1e-7);
    EXPECT_NEAR(b.value - a.value, 1e-7 * a.slope, 1e-9 * std::abs(a.value) + 1e-12) << lambda;
  }
}

TEST(StiffnessTable, PaperSecantForceIsAboutHalfTheEnergyConsistentOne) {
  // model.md: F = k_s lambda gives only about half the SEDF stress.
  const StrainEnergy energy(test::porcineLiver());
  const StiffnessTable table(energy);
  const double area = energy.parameters().springArea_m2;
  for (const double lambda : {1.05, 1.15, 1.3}) {
    const double ratio = table.springStiffness(lambda) * lambda / area / table.stress(lambda);
    EXPECT_GT(ratio, 0.3) << lambda;
    EXPECT_LT(ratio, 0.7) << lambda;
  }
}

}  // namespace
}  // namespace tissuesim
