// SPDX-License-Identifier: Apache-2.0
#include "analysis/UniaxialExperiment.h"

#include <algorithm>

#include <gtest/gtest.h>

#include "analysis/GoodnessOfFit.h"
#include "fem/IsochoricSoftening.h"
#include "support/TestTissues.h"

namespace tissuesim {
namespace {

class UniaxialCycles : public ::testing::Test {
 protected:
  StrainEnergy m_energy{test::porcineLiver()};
  StiffnessTable m_table{m_energy};
  UniaxialExperiment m_test{m_energy, m_table};
  UniaxialProtocol m_paperProtocol{{1.15, 1.23, 1.30}, 100};
};

TEST_F(UniaxialCycles, BranchesFollowTheProtocol) {
  const auto branches = m_test.run(UniaxialModel::Sedf, m_paperProtocol);
  ASSERT_EQ(branches.size(), 6u);
  for (std::size_t b = 0; b < branches.size(); ++b) {
    const CurveBranch& branch = branches[b];
    EXPECT_EQ(branch.cycle, static_cast<int>(b / 2) + 1);
    EXPECT_EQ(branch.phase, b % 2 == 0 ? LoadPhase::Loading : LoadPhase::Unloading);
    ASSERT_EQ(branch.stretch.size(), 100u);
    ASSERT_EQ(branch.stress_Pa.size(), 100u);
    const double peak = m_paperProtocol.lambdaMax[b / 2];
    const bool loading = branch.phase == LoadPhase::Loading;
    EXPECT_DOUBLE_EQ(branch.stretch.front(), loading ? 1.0 : peak);
    EXPECT_DOUBLE_EQ(branch.stretch.back(), loading ? peak : 1.0);
    EXPECT_TRUE(std::is_sorted(branch.stretch.begin(), branch.stretch.end(),
                               [&](double a, double c) { return loading ? a < c : a > c; }));
  }
}

TEST_F(UniaxialCycles, StateCarriesOverBetweenCycles) {
  const auto branches = m_test.run(UniaxialModel::Sedf, m_paperProtocol);
  const CurveBranch& secondLoading = branches[2];  // cycle 2, up to 1.23, after a peak of 1.15
  for (std::size_t i = 1; i < secondLoading.stretch.size(); ++i) {
    const double lambda = secondLoading.stretch[i];
    if (lambda < 1.149) {
      EXPECT_LT(secondLoading.stress_Pa[i], m_energy.stress(lambda)) << "softened " << lambda;
    } else if (lambda > 1.151) {
      EXPECT_EQ(secondLoading.stress_Pa[i], m_energy.stress(lambda)) << "virgin " << lambda;
    }
  }
}

TEST_F(UniaxialCycles, EnergyConsistentSpringReproducesTheContinuum) {
  const auto sedf = m_test.run(UniaxialModel::Sedf, m_paperProtocol);
  const auto eesm = m_test.run(UniaxialModel::Eesm, m_paperProtocol);
  for (std::size_t b = 0; b < sedf.size(); ++b) {
    EXPECT_GT(coefficientOfDetermination(sedf[b].stress_Pa, eesm[b].stress_Pa), 0.999999);
  }
}

TEST_F(UniaxialCycles, PaperSecantSpringAndLinearSpringFallShort) {
  const auto sedf = m_test.run(UniaxialModel::Sedf, m_paperProtocol);
  const auto paper = m_test.run(UniaxialModel::EesmPaper, m_paperProtocol);
  const auto smm = m_test.run(UniaxialModel::Smm, m_paperProtocol);
  for (std::size_t b = 0; b < sedf.size(); b += 2) {  // loading branches
    EXPECT_LT(coefficientOfDetermination(sedf[b].stress_Pa, paper[b].stress_Pa), 0.9);
    EXPECT_LT(coefficientOfDetermination(sedf[b].stress_Pa, smm[b].stress_Pa), 0.9);
  }
}

TEST_F(UniaxialCycles, LinearSpringIsTheLeastSquaresFit) {
  const auto sedf = m_test.run(UniaxialModel::Sedf, m_paperProtocol);
  const auto smm = m_test.run(UniaxialModel::Smm, m_paperProtocol);
  const double modulus = UniaxialExperiment::fitLinearModulus(sedf);
  EXPECT_GT(modulus, 0.0);
  // Least squares: residuals are orthogonal to the regressor (lambda - 1).
  double orthogonality = 0.0;
  double scale = 0.0;
  for (std::size_t b = 0; b < sedf.size(); ++b) {
    for (std::size_t i = 0; i < sedf[b].stretch.size(); ++i) {
      const double strain = sedf[b].stretch[i] - 1.0;
      EXPECT_DOUBLE_EQ(smm[b].stress_Pa[i], modulus * strain);
      orthogonality += (sedf[b].stress_Pa[i] - smm[b].stress_Pa[i]) * strain;
      scale += std::abs(sedf[b].stress_Pa[i] * strain);
    }
  }
  EXPECT_LT(std::abs(orthogonality), 1e-12 * scale);
}

TEST_F(UniaxialCycles, TheFemsMaterialPointSoftensWithoutAPermanentSet) {
  // The FEM's points soften through I1bar, the residual strain left out: the first loading is
  // the continuum's virgin curve, each unloading is virgin times the spring law's F (with the
  // FEM's rounded onset) at the same stretch, and the tissue unloads to no stress at rest, where
  // the paper's sedf curve keeps the residual stress of its permanent set.
  const auto fem = m_test.run(UniaxialModel::Fem, m_paperProtocol);
  const auto sedf = m_test.run(UniaxialModel::Sedf, m_paperProtocol);
  ASSERT_EQ(fem.size(), sedf.size());
  const StressSoftening softening(m_energy.parameters(), kIsochoricSofteningOnsetMeasure);
  for (std::size_t i = 0; i < fem[0].stretch.size(); ++i)
    EXPECT_DOUBLE_EQ(fem[0].stress_Pa[i], m_energy.stress(fem[0].stretch[i])) << i;
  for (std::size_t b = 1; b < fem.size(); b += 2) {
    const double peak = m_paperProtocol.lambdaMax[b / 2];
    const CurveBranch& unloading = fem[b];
    for (std::size_t i = 0; i < unloading.stretch.size(); ++i) {
      const double lambda = unloading.stretch[i];
      EXPECT_NEAR(unloading.stress_Pa[i], m_energy.stress(lambda) * softening.factor(lambda, peak),
                  1e-9 * m_energy.stress(peak))
          << "cycle " << b / 2 + 1 << " at " << lambda;
    }
    EXPECT_EQ(unloading.stress_Pa.back(), 0.0) << "no stress at rest";
    EXPECT_LT(sedf[b].stress_Pa.back(), 0.0) << "the paper's permanent set";
  }
  // Reloaded below the last peak it follows its unloading, and the virgin curve past it.
  const CurveBranch& reloading = fem[2];
  for (std::size_t i = 0; i < reloading.stretch.size(); ++i) {
    const double lambda = reloading.stretch[i];
    const double expected = lambda < 1.15 ? m_energy.stress(lambda) * softening.factor(lambda, 1.15)
                                          : m_energy.stress(lambda);
    EXPECT_NEAR(reloading.stress_Pa[i], expected, 1e-9 * m_energy.stress(1.23)) << lambda;
  }
}

TEST_F(UniaxialCycles, RejectsBadProtocols) {
  EXPECT_THROW(m_test.validate({{1.0}, 100}), std::invalid_argument);
  EXPECT_THROW(m_test.validate({{0.8}, 100}), std::invalid_argument);
  EXPECT_THROW(m_test.validate({{1.2, 1.6}, 100}), std::invalid_argument);
  EXPECT_THROW(m_test.validate({{1.2}, 1}), std::invalid_argument);
  EXPECT_THROW(m_test.validate({{}, 100}), std::invalid_argument);
  EXPECT_NO_THROW(m_test.validate({{m_table.range().upper}, 2}));
  EXPECT_THROW(m_test.validate({{m_table.range().upper + 1e-9}, 2}), std::invalid_argument);
}

TEST_F(UniaxialCycles, JustBelowLockingStaysFinite) {
  const UniaxialProtocol extreme{{m_table.range().upper}, 200};
  for (const UniaxialModel model :
       {UniaxialModel::Sedf, UniaxialModel::Eesm, UniaxialModel::EesmPaper, UniaxialModel::Smm}) {
    for (const CurveBranch& branch : m_test.run(model, extreme)) {
      for (const double stress : branch.stress_Pa) EXPECT_TRUE(std::isfinite(stress));
    }
  }
}

}  // namespace
}  // namespace tissuesim
