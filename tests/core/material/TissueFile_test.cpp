// SPDX-License-Identifier: Apache-2.0
#include "material/TissueFile.h"

#include <string>

#include <gtest/gtest.h>

#include "support/TestTissues.h"

namespace tissuesim {
namespace {

TEST(TissueFile, BundledLiverLoadsInSIUnits) {
  const TissueParameters p = test::porcineLiver();
  EXPECT_DOUBLE_EQ(p.mu_Pa, 100.0);  // 0.1 kPa
  EXPECT_DOUBLE_EQ(p.chainSegmentsN, 1.1974);
  EXPECT_DOUBLE_EQ(p.A1_Pa, 9675.4);
  EXPECT_DOUBLE_EQ(p.A2_Pa, 7543600.0);
  EXPECT_DOUBLE_EQ(p.fibreFraction, 0.2755);
  EXPECT_DOUBLE_EQ(p.softeningB, 3.3389);
  EXPECT_DOUBLE_EQ(p.softeningC_Pa, 9527.3);
  EXPECT_EQ(p.softeningExponentN, 1);
  EXPECT_DOUBLE_EQ(p.springArea_m2, 3.569e-5);
  EXPECT_DOUBLE_EQ(p.density_kg_m3, 1060.0);
  EXPECT_EQ(p.inverseLangevin, InverseLangevin::Puso);
  EXPECT_FALSE(p.source.empty());
}

TEST(TissueFile, OptionalFieldsAreRead) {
  const TissueParameters p = loadTissueFile(test::tissueDataPath("valid-exact-n2.json"));
  EXPECT_EQ(p.softeningExponentN, 2);
  EXPECT_EQ(p.inverseLangevin, InverseLangevin::Exact);
  EXPECT_DOUBLE_EQ(p.density_kg_m3, 1000.0);
  EXPECT_DOUBLE_EQ(p.damageStretch, 1.3);
  EXPECT_EQ(p.name, "test");
  EXPECT_DOUBLE_EQ(test::porcineLiver().damageStretch, 1.18);  // the bundled file's
}

struct BadTissueCase {
  const char* file;
  const char* expected;  // must appear in the message, after the file name
};

class BadTissueFile : public ::testing::TestWithParam<BadTissueCase> {};

TEST_P(BadTissueFile, IsRefusedWithOneLineNamingFileAndField) {
  const std::string path = test::tissueDataPath(GetParam().file);
  try {
    loadTissueFile(path);
    FAIL() << GetParam().file << " was accepted";
  } catch (const TissueFileError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(GetParam().expected), std::string::npos)
        << "message: " << message << "\nexpected to contain: " << GetParam().expected;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadTissueFile,
    ::testing::Values(
        BadTissueCase{"empty.json", "the file is empty"},
        BadTissueCase{"whitespace-only.json", "the file is empty"},
        BadTissueCase{"not-json.json", "line 1, column 1: not valid JSON"},
        BadTissueCase{"missing-comma.json", "line 4, column 10: not valid JSON"},
        BadTissueCase{"binary-garbage.json", "contains binary data"},
        BadTissueCase{"top-level-array.json", "expected a JSON object"},
        BadTissueCase{"missing-mu.json", "missing field 'mu_kpa'"},
        BadTissueCase{"wrong-type.json", "field 'N' must be a number"},
        BadTissueCase{"nan-modulus.json", "field 'mu_kpa' is NaN, which is not a finite number"},
        BadTissueCase{"infinite-modulus.json", "field 'A2_kpa' is 1e999, which is not a finite"},
        BadTissueCase{"negative-modulus.json", "field 'mu_kpa' = -0.1 is out of range"},
        BadTissueCase{"fraction-above-one.json", "field 'f' = 1.5 is out of range"},
        BadTissueCase{"fraction-below-zero.json", "field 'f' = -0.01 is out of range"},
        BadTissueCase{"n-segments-below-one.json", "field 'N' = 0.9 is out of range"},
        BadTissueCase{"n-segments-equal-one.json", "lambda = 1 is inadmissible"},
        BadTissueCase{"softening-exponent-three.json", "field 'n' = 3 is out of range"},
        BadTissueCase{"softening-exponent-fraction.json", "field 'n' must be the integer 1 or 2"},
        BadTissueCase{"unknown-key.json", "unknown field 'mu'"},
        BadTissueCase{"unknown-langevin.json", "field 'inverse_langevin' = \"pade\""},
        BadTissueCase{"zero-softening-modulus.json", "field 'C_kpa' = 0 is out of range"},
        BadTissueCase{"negative-density.json", "field 'density_kg_m3' = -1060 is out of range"},
        BadTissueCase{"damage-stretch-one.json", "field 'damage_stretch' = 1 is out of range"},
        BadTissueCase{"does-not-exist.json", "cannot open the tissue file"}),
    [](const ::testing::TestParamInfo<BadTissueCase>& testCase) {
      std::string name = testCase.param.file;
      name = name.substr(0, name.find('.'));
      for (char& c : name) {
        if (c == '-') c = '_';
      }
      return name;
    });

TEST(TissueFile, DirectoryIsRefused) {
  EXPECT_THROW(loadTissueFile(TISSUESIM_TEST_DATA_DIR), TissueFileError);
}

}  // namespace
}  // namespace tissuesim
