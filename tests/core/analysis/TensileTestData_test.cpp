// SPDX-License-Identifier: Apache-2.0
#include "analysis/TensileTestData.h"

#include <gtest/gtest.h>

#include <string>

namespace tissuesim {
namespace {

std::string fitData(const std::string& name) {
  return std::string(TISSUESIM_TEST_DATA_DIR) + "/fit/" + name;
}

std::string errorOf(const std::string& name,
                    const std::optional<SpecimenGeometry>& specimen = std::nullopt) {
  try {
    readTensileTestCsv(fitData(name), specimen);
  } catch (const TestDataError& error) {
    return error.what();
  }
  return "(accepted)";
}

TEST(TensileTestData, ReadsWhatUniaxialWrites) {
  const std::vector<CurveBranch> branches = readTensileTestCsv(fitData("liver-uniaxial.csv"));
  ASSERT_EQ(branches.size(), 6u);
  EXPECT_EQ(branches[0].cycle, 1);
  EXPECT_EQ(branches[0].phase, LoadPhase::Loading);
  EXPECT_EQ(branches[5].cycle, 3);
  EXPECT_EQ(branches[5].phase, LoadPhase::Unloading);
  EXPECT_EQ(branches[0].stretch.size(), 25u);
  EXPECT_DOUBLE_EQ(branches[0].stretch.front(), 1.0);
  EXPECT_NEAR(branches[4].stretch.back(), 1.30, 1e-12);
  EXPECT_GT(branches[4].stress_Pa.back(), 100e3);  // kPa in the file, Pa here
}

TEST(TensileTestData, CutsADisplacementForceSequenceWhereTheStretchTurns) {
  // 5 mm of a 50 mm gauge is lambda 1.1; 1 N on 10 mm^2 is 100 kPa.
  const std::vector<CurveBranch> branches =
      readTensileTestCsv(fitData("displacement-force.csv"), SpecimenGeometry{50.0, 10.0});
  ASSERT_EQ(branches.size(), 2u);
  EXPECT_EQ(branches[0].phase, LoadPhase::Loading);
  EXPECT_EQ(branches[1].phase, LoadPhase::Unloading);
  EXPECT_EQ(branches[1].cycle, 1);
  EXPECT_NEAR(branches[0].stretch.back(), 1.2, 1e-12);
  EXPECT_NEAR(branches[0].stress_Pa.back(), 100e3, 1e-6);
  EXPECT_EQ(branches[1].stretch.front(), branches[0].stretch.back()) << "the turning point in both";
  EXPECT_NE(errorOf("displacement-force.csv").find("--length-mm, --area-mm2"), std::string::npos);
}

TEST(TensileTestData, BadDataGetsOneLineNamingTheFileAndLine) {
  for (const auto& [file, expected] : std::vector<std::pair<std::string, std::string>>{
           {"not-numeric.csv", "not-numeric.csv:3: 'abc' in column stress_kpa is not a number"},
           {"wrong-header.csv", "wrong-header.csv:1: header 'lambda,force' is not one of"},
           {"missing-value.csv", "missing-value.csv:3: 3 values where the header names 4"},
           {"falling-loading.csv",
            "falling-loading.csv:4: the loading branch of cycle 1 falls from 1.1"},
           {"nan.csv", "nan.csv:3: column stress_kpa is not a finite number"},
           // Found by fuzzing: converted to int before it was checked (undefined behaviour).
           {"huge-cycle.csv", "huge-cycle.csv:2: cycle '1e44' is not 1, 2, ... (at most 10^6)"},
           {"empty.csv", "empty.csv: the file is empty"},
           {"negative-stretch.csv",
            "negative-stretch.csv:3: a stretch of -0.500000 is not positive"},
           {"no-such-file.csv", "no-such-file.csv: cannot open the test data"}}) {
    const std::string message = errorOf(file);
    EXPECT_NE(message.find(expected), std::string::npos) << file << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace tissuesim
