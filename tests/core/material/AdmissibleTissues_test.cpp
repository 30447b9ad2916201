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

namespace tissuesim {
namespace {

struct Corner {
  const char* what;
  double mu_kpa, N, A1_kpa, A2_kpa, f, b, C_kpa;
};

std::string tissueJson(const Corner& c) {
  return "{\"mu_kpa\": " + std::to_string(c.mu_kpa) + ", \"N\": " + std::to_string(c.N) +
         ", \"A1_kpa\": " + std::to_string(c.A1_kpa) + ", \"A2_kpa\": " + std::to_string(c.A2_kpa) +
         ", \"f\": " + std::to_string(c.f) + ", \"b\": " + std::to_string(c.b) +
         ", \"C_kpa\": " + std::to_string(c.C_kpa) + ", \"v_ij_m2\": 3.569e-5}";
}

TEST(AdmissibleTissues, TheCornersOfTheAdmittedRangesGiveFiniteTablesAndForces) {
  const std::vector<Corner> corners = {
      {"the paper's liver", 0.1, 1.1974, 9.6754, 7543.6, 0.2755, 3.3389, 9.5273},
      {"every modulus at its bound", 1e6, 1.1974, 1e6, 1e6, 0.5, 3.0, 1e6},
      {"nearly Gaussian (N at its bound)", 0.1, 1e8, 9.7, 7543.6, 0.2755, 3.3, 9.5},
      {"N = 10^6 (was std::bad_alloc)", 0.1, 1e6, 9.7, 7543.6, 0.2755, 3.3, 9.5},
      {"barely above locking at rest", 0.1, 1.000001, 9.7, 7543.6, 0.2755, 3.3, 9.5},
      {"softest network, no fibres", 1e-6, 2.0, 0.0, 0.0, 0.0, 0.0, 1e-6},
      {"all fibre, strongest softening", 0.1, 1.2, 1e6, 1e6, 1.0, 1e6, 1e-6},
  };
  for (const Corner& corner : corners) {
    SCOPED_TRACE(corner.what);
    const TissueParameters parameters = parseTissueJson(tissueJson(corner), corner.what);
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
           {"mu_kpa", tissueJson({"", 1e308, 1.2, 9.7, 7543.6, 0.28, 3.3, 9.5})},
           {"A2_kpa", tissueJson({"", 0.1, 1.2, 9.7, 1e308, 0.28, 3.3, 9.5})},
           {"C_kpa", tissueJson({"", 0.1, 1.2, 9.7, 7543.6, 0.28, 3.3, 1e308})},
           {"N", tissueJson({"", 0.1, 1e300, 9.7, 7543.6, 0.28, 3.3, 9.5})},
           {"b", tissueJson({"", 0.1, 1.2, 9.7, 7543.6, 0.28, 1e300, 9.5})}}) {
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
