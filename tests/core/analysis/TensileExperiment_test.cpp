// SPDX-License-Identifier: Apache-2.0
#include "analysis/TensileExperiment.h"

#include <gtest/gtest.h>

#include "analysis/GoodnessOfFit.h"
#include "fem/FemModel.h"
#include "support/TestSystems.h"

namespace tissuesim {
namespace {

class TensileCurves : public ::testing::Test {
 protected:
  const test::LiverMaterial& m_liver = test::LiverMaterial::instance();
  // A coarse specimen (1 cell across 5 mm) keeps the test quick; the CLI default is 2.
  TensileExperiment m_test{m_liver.energy, m_liver.table, {{0.055, 0.020, 0.005}, 1}};
  UniaxialProtocol m_protocol{{1.15, 1.23}, 8};
  UniaxialExperiment m_continuum{m_liver.energy, m_liver.table};
};

TEST_F(TensileCurves, CalibratedNetworkFollowsTheContinuumAndUncalibratedDoesNot) {
  const double calibration = m_test.smallStrainCalibration(m_liver.energy.initialShearModulus());
  // A central-force network without the continuum's lateral contraction is several times softer.
  EXPECT_GT(calibration, 3.0);
  EXPECT_LT(calibration, 10.0);
  const auto reference = m_continuum.run(UniaxialModel::Sedf, m_protocol);
  TensileOptions options;
  options.volumeScale = calibration;
  TensilePointStats stats;
  const auto calibrated = m_test.run(options, m_protocol, &stats);
  EXPECT_EQ(stats.unconvergedPoints, 0);
  EXPECT_LE(stats.worstRelativeResidual, options.forceTolerance_N);
  options.volumeScale = 1.0;
  const auto raw = m_test.run(options, m_protocol);
  for (std::size_t b = 0; b < reference.size(); ++b) {
    const double r2 = coefficientOfDetermination(reference[b].stress_Pa, calibrated[b].stress_Pa);
    EXPECT_GT(r2, b % 2 == 0 ? 0.999 : 0.99) << "branch " << b;
    EXPECT_LT(coefficientOfDetermination(reference[b].stress_Pa, raw[b].stress_Pa), 0.5);
  }
}

TEST_F(TensileCurves, WithTheVolumeTermTheRefittedCalibrationHoldsTheCurveOverThePapersCycles) {
  // The bundled scene's 100 kPa: the springs' own factor leaves the first cycle's loading at
  // R^2 99.4 %; refitted with the term in place, every loading branch is at 99.9 % or above
  // and every unloading one at 99 % or above (the simulator's requirement), with a factor a few
  // per cent under the springs' own.
  constexpr double kBulk_Pa = 1e5;
  const double mu0 = m_liver.energy.initialShearModulus();
  const double springsOnly = m_test.smallStrainCalibration(mu0);
  const double refitted = m_test.volumeTermCalibration(mu0, kBulk_Pa);
  EXPECT_LT(refitted, springsOnly);
  EXPECT_GT(refitted, 0.9 * springsOnly);
  EXPECT_DOUBLE_EQ(m_test.volumeTermCalibration(mu0, 0.0), springsOnly);
  const UniaxialProtocol cycles{{1.15, 1.23, 1.30}, 10};
  const auto reference = m_continuum.run(UniaxialModel::Sedf, cycles);
  TensileOptions options;
  options.bulkModulus_Pa = kBulk_Pa;
  options.volumeScale = springsOnly;
  const auto before = m_test.run(options, cycles);
  EXPECT_LT(coefficientOfDetermination(reference[0].stress_Pa, before[0].stress_Pa), 0.999);
  options.volumeScale = refitted;
  const auto after = m_test.run(options, cycles);
  for (std::size_t b = 0; b < reference.size(); ++b) {
    EXPECT_GE(coefficientOfDetermination(reference[b].stress_Pa, after[b].stress_Pa),
              b % 2 == 0 ? 0.999 : 0.99)
        << "branch " << b;
  }
}

TEST_F(TensileCurves, TimeIntegratorsReachTheSameEquilibria) {
  TensileOptions options;
  options.volumeScale = 5.0;
  options.isSoftening = false;
  const UniaxialProtocol protocol{{1.1}, 3};
  const auto statics = m_test.run(options, protocol);
  options.integrator = "implicit";
  options.forceTolerance_N = 1e-7;
  TensilePointStats stats;
  const auto dynamic = m_test.run(options, protocol, &stats);
  EXPECT_EQ(stats.unconvergedPoints, 0);
  for (std::size_t i = 0; i < statics[0].stress_Pa.size(); ++i) {
    EXPECT_NEAR(dynamic[0].stress_Pa[i], statics[0].stress_Pa[i],
                1e-4 * std::abs(statics[0].stress_Pa.back()));
  }
}

TEST_F(TensileCurves, JustBelowLockingStaysFiniteAndConverged) {
  TensileOptions options;
  options.volumeScale = 5.8;
  TensilePointStats stats;
  const auto curve = m_test.run(options, {{m_liver.table.range().upper - 1e-3}, 4}, &stats);
  EXPECT_EQ(stats.unconvergedPoints, 0);
  for (const auto& branch : curve) {
    for (const double stress : branch.stress_Pa) EXPECT_TRUE(std::isfinite(stress));
  }
  EXPECT_THROW(m_test.run(options, {{1.6}, 4}), std::invalid_argument);
}

TEST_F(TensileCurves, TheLatticeFemFollowsTheVirginCurveWhenItsBulkModulusHoldsTheVolume) {
  // The isochoric tets with the volume term per cube (a scene's effects.model fem) have no
  // softening: every branch is the virgin curve. At the FEM's bulk modulus (200 times the
  // tissue's stiffest tangent up to 1.3) the strip keeps its volume and its loading is the
  // continuum's; at the bundled scene's 100 kPa it thins as it stretches and falls far short.
  const UniaxialProtocol protocol{{1.15, 1.3}, 6};
  const auto virginFit = [&](double bulkModulus_Pa) {
    TensileOptions options;
    options.model = LatticeModel::IsochoricTets;
    options.bulkModulus_Pa = bulkModulus_Pa;
    TensilePointStats stats;
    const auto curve = m_test.run(options, protocol, &stats);
    EXPECT_EQ(stats.unconvergedPoints, 0);
    EXPECT_GT(stats.tets, 0);
    double worst = 1.0;
    for (const auto& branch : curve) {
      std::vector<double> virgin;
      for (const double lambda : branch.stretch) virgin.push_back(m_liver.energy.stress(lambda));
      worst = std::min(worst, coefficientOfDetermination(virgin, branch.stress_Pa));
    }
    return worst;
  };
  EXPECT_GE(virginFit(defaultFemBulkModulus(m_liver.energy)), 0.9999);
  EXPECT_LT(virginFit(1e5), 0.95);
  TensileOptions withoutVolume;
  withoutVolume.model = LatticeModel::IsochoricTets;
  EXPECT_THROW(m_test.run(withoutVolume, protocol), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
