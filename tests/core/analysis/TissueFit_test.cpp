// SPDX-License-Identifier: Apache-2.0
#include "analysis/TissueFit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "analysis/TensileTestData.h"
#include "material/TissueFile.h"
#include "support/TestTissues.h"

namespace tissuesim {
namespace {

/// The paper's protocol (Section 6) on the continuum model of `parameters`, each stress times
/// (1 + noise * a standard normal draw).
std::vector<CurveBranch> synthesised(const TissueParameters& parameters, double noise,
                                     unsigned seed) {
  std::vector<CurveBranch> data = protocolStretches({{1.15, 1.23, 1.30}, 25});
  for (CurveBranch& branch : data) branch.stress_Pa.assign(branch.stretch.size(), 0.0);
  const std::vector<std::vector<double>> stresses = modelStresses(parameters, data);
  std::mt19937 random(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (std::size_t b = 0; b < data.size(); ++b) {
    for (std::size_t i = 0; i < data[b].stretch.size(); ++i)
      data[b].stress_Pa[i] = stresses[b][i] * (1.0 + noise * normal(random));
  }
  return data;
}

double valueOf(const TissueFitResult& result, const std::string& name) {
  for (const FittedParameter& entry : result.table) {
    if (entry.name == name) return entry.value;
  }
  ADD_FAILURE() << name;
  return 0.0;
}

TEST(TissueFit, ThePapersLiverReproducesItsOwnCurve) {
  const TissueParameters liver = test::porcineLiver();
  TissueFitOptions options;
  options.base = liver;
  options.base.mu_Pa *= 3.0;  // start away from the answer
  options.base.A2_Pa *= 0.5;
  const TissueFitResult result = fitTissue(synthesised(liver, 0.0, 1), options);
  ASSERT_EQ(result.branches.size(), 6u);
  for (const BranchFit& branch : result.branches) EXPECT_GT(branch.rSquared, 0.999);
  EXPECT_NEAR(valueOf(result, "A2_kpa"), liver.A2_Pa / 1000.0, 0.01 * liver.A2_Pa / 1000.0);
  EXPECT_NEAR(valueOf(result, "b"), liver.softeningB, 0.01 * liver.softeningB);
  EXPECT_EQ(valueOf(result, "f"), liver.fibreFraction) << "f is held";
  EXPECT_FALSE(result.notes.empty());
}

TEST(TissueFit, RecoversWhatTheDataIdentifyFromNoisyDataAndSaysWhatTheyDoNot) {
  // Another tissue than the starting one, its curve with 1 % noise.
  TissueParameters truth = test::porcineLiver();
  truth.mu_Pa = 300.0;
  truth.chainSegmentsN = 1.35;
  truth.A1_Pa = 20e3;
  truth.A2_Pa = 3000e3;
  truth.softeningB = 2.0;
  truth.softeningC_Pa = 15e3;
  TissueFitOptions options;
  options.base = test::porcineLiver();
  const std::vector<CurveBranch> noisy = synthesised(truth, 0.01, 7);
  const TissueFitResult result = fitTissue(noisy, options);
  for (const BranchFit& branch : result.branches)
    EXPECT_GT(branch.rSquared, 0.999) << branch.cycle << " " << phaseName(branch.phase);
  // Each parameter is either identified and near the truth (within three standard errors or
  // 10 %), or reported as not identified with a warning naming it.
  const TissueParameters& fitted = result.parameters;
  const std::vector<std::pair<std::string, std::pair<double, double>>> compared = {
      {"mu_kpa", {fitted.mu_Pa, truth.mu_Pa}},
      {"N", {fitted.chainSegmentsN, truth.chainSegmentsN}},
      {"A1_kpa", {fitted.A1_Pa, truth.A1_Pa}},
      {"A2_kpa", {fitted.A2_Pa, truth.A2_Pa}},
      {"b", {fitted.softeningB, truth.softeningB}},
      {"C_kpa", {fitted.softeningC_Pa, truth.softeningC_Pa}}};
  int identified = 0;
  for (const auto& [name, values] : compared) {
    const FittedParameter& entry = *std::find_if(result.table.begin(), result.table.end(),
                                                 [&](const auto& e) { return e.name == name; });
    if (entry.isIdentified) {
      ++identified;
      const double scale = name.find("_kpa") != std::string::npos ? 1000.0 : 1.0;
      EXPECT_LE(std::abs(values.first - values.second),
                std::max(3.0 * entry.uncertainty * scale, 0.10 * values.second))
          << name << " = " << entry.value << " +- " << entry.uncertainty;
    } else {
      bool isWarned = false;
      for (const std::string& warning : result.warnings)
        isWarned = isWarned || warning.rfind(name + " is not identified", 0) == 0;
      EXPECT_TRUE(isWarned) << name;
    }
  }
  EXPECT_GE(identified, 3) << "the fibre moduli and b, at least";
}

TEST(TissueFit, TheFittedTissueIsAFileTheSimulatorReads) {
  const TissueFitResult result = fitTissue(
      readTensileTestCsv(std::string(TISSUESIM_TEST_DATA_DIR) + "/fit/liver-uniaxial.csv"),
      {test::porcineLiver(), {}, 4, {}});
  const TissueParameters read = parseTissueJson(tissueFileText(result.parameters, "a note"), "t");
  EXPECT_EQ(read.mu_Pa, result.parameters.mu_Pa);
  EXPECT_EQ(read.chainSegmentsN, result.parameters.chainSegmentsN);
  EXPECT_EQ(read.A2_Pa, result.parameters.A2_Pa);
  EXPECT_EQ(read.softeningC_Pa, result.parameters.softeningC_Pa);
  EXPECT_EQ(read.springArea_m2, result.parameters.springArea_m2);
}

TEST(TissueFit, TooFewPointsOrAnUnknownFixedNameIsRefused) {
  const std::vector<CurveBranch> three =
      readTensileTestCsv(std::string(TISSUESIM_TEST_DATA_DIR) + "/fit/three-points.csv");
  try {
    fitTissue(three, {test::porcineLiver(), {}, 2, {}});
    ADD_FAILURE() << "three points for four parameters accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("3 points for 4 free parameters"), std::string::npos)
        << error.what();
  }
  // Holding two leaves two unknowns: three points do.
  EXPECT_NO_THROW(fitTissue(three, {test::porcineLiver(), {"mu_kpa", "N"}, 2, {}}));
  EXPECT_THROW(fitTissue(three, {test::porcineLiver(), {"shear"}, 2, {}}), std::invalid_argument);
}

TEST(TissueFit, AParameterIsSetInTheTissueFilesUnit) {
  TissueParameters p = test::porcineLiver();
  setFitParameter(p, "A2_kpa", 3000.0);
  setFitParameter(p, "N", 1.4);
  EXPECT_EQ(p.A2_Pa, 3e6);
  EXPECT_EQ(p.chainSegmentsN, 1.4);
  EXPECT_EQ(p.mu_Pa, test::porcineLiver().mu_Pa) << "the others untouched";
  try {
    setFitParameter(p, "shear", 1.0);
    ADD_FAILURE() << "an unknown name accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("expected one of mu_kpa, N, f, A1_kpa"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace tissuesim
