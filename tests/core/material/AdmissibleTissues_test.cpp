// SPDX-License-Identifier: Apache-2.0
// Every tissue the file's validation admits gives finite tables, stresses and stiffnesses over
// the stretches the program uses, in a table of bounded size: the corners of the admitted ranges
// (docs/tissue-file.md), loaded through the parser as an instructor's file would be.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "material/StiffnessTable.h"
#include "material/StrainEnergy.h"
#include "material/TissueFile.h"
#include "springs/SpringForceLaw.h"
#include "support/AdmittedTissueCorners.h"

namespace tissuesim {
namespace {

TEST(AdmissibleTissues, TheCornersOfTheAdmittedRangesGiveFiniteTablesAndForces) {
  for (const test::TissueCorner& corner : test::admittedTissueCorners()) {
    SCOPED_TRACE(corner.what);
    const TissueParameters parameters = parseTissueJson(test::tissueJson(corner), corner.what);
    const StrainEnergy energy(parameters);
    const StiffnessTable table(energy);
    const StretchRange range = table.range();
    EXPECT_LT(range.lower, 1.0);
    EXPECT_GT(range.upper, 1.0);
    EXPECT_GE(range.lower, 1.0 / 3.0 - 1e-12);
    EXPECT_LE(range.upper, 3.0 + 1e-12);
    EXPECT_LE(table.nodeCount(), 100000u);  // a few MB at most
    const SpringForceLaw law(SpringLaw::Eesm, table, parameters, 0.0, /*isSoftening=*/true);
    for (int i = 0; i <= 200; ++i) {
      const double lambda = range.lower + (range.upper - range.lower) * i / 200.0;
      ASSERT_TRUE(std::isfinite(table.energy(lambda))) << lambda;
      const HermiteNode stress = table.stressAndSlope(lambda);
      ASSERT_TRUE(std::isfinite(stress.value) && std::isfinite(stress.slope)) << lambda;
      // Softened: unloading from the top of the range and from halfway.
      for (const double peak : {range.upper, 0.5 * (1.0 + range.upper)}) {
        const SpringStress softened = law.evaluate(lambda, peak);
        ASSERT_TRUE(std::isfinite(softened.stress) && std::isfinite(softened.slope))
            << lambda << " after " << peak;
      }
    }
  }
}

TEST(AdmissibleTissues, WhatWouldOverflowIsRefusedWithTheField) {
  // 1e308 kPa is 1e311 Pa: infinity. Each bound names its field.
  for (const auto& [field, json] : std::vector<std::pair<std::string, std::string>>{
           {"mu_kpa", test::tissueJson({"", 1e308, 1.2, 9.7, 7543.6, 0.28, 3.3, 9.5})},
           {"A2_kpa", test::tissueJson({"", 0.1, 1.2, 9.7, 1e308, 0.28, 3.3, 9.5})},
           {"C_kpa", test::tissueJson({"", 0.1, 1.2, 9.7, 7543.6, 0.28, 3.3, 1e308})},
           {"N", test::tissueJson({"", 0.1, 1e300, 9.7, 7543.6, 0.28, 3.3, 9.5})},
           {"b", test::tissueJson({"", 0.1, 1.2, 9.7, 7543.6, 0.28, 1e300, 9.5})}}) {
    try {
      parseTissueJson(json, "t.json");
      ADD_FAILURE() << field << " accepted";
    } catch (const std::exception& error) {
      EXPECT_NE(std::string(error.what()).find("field '" + field + "'"), std::string::npos)
          << error.what();
    }
  }
}

}  // namespace
}  // namespace tissuesim
