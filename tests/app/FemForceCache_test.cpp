// SPDX-License-Identifier: Apache-2.0
// organ-poke's kept FEM forces: read back to the bit under their key, not used under another key
// or for a depth they lack, and a file that is not such a file refused naming its line.

#include "app/FemForceCache.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "app/CommandError.h"

namespace tissuesim::app {
namespace {

class FemForceCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    m_path = (std::filesystem::temp_directory_path() /
              ("fem-cache-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
               "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".csv"))
                 .string();
    std::filesystem::remove(m_path);
  }
  void TearDown() override { std::filesystem::remove(m_path); }
  void write(const std::string& text) const { std::ofstream(m_path) << text; }

  std::string m_path;
};

std::uint64_t keyOf(double number, const std::string& text) {
  FemReferenceKey key;
  key.addNumber(number);
  key.addText(text);
  return key.value();
}

TEST(FemReferenceKey, DependsOnEveryInputToTheBitAndOnItsOrder) {
  EXPECT_EQ(keyOf(0.0025, "mesh"), keyOf(0.0025, "mesh"));
  EXPECT_NE(keyOf(0.0025, "mesh"), keyOf(std::nextafter(0.0025, 1.0), "mesh"));
  EXPECT_NE(keyOf(0.0025, "mesh"), keyOf(0.0025, "mesh2"));
  FemReferenceKey ab, ba;
  ab.addText("a");
  ab.addText("b");
  ba.addText("b");
  ba.addText("a");
  EXPECT_NE(ab.value(), ba.value());
  // Text boundaries count: "ab" then "" is not "a" then "b".
  FemReferenceKey joined, split;
  joined.addText("ab");
  joined.addText("");
  split.addText("a");
  split.addText("b");
  EXPECT_NE(joined.value(), split.value());
}

TEST_F(FemForceCacheTest, ReadsBackWhatItWroteToTheBit) {
  const std::vector<double> depths{1.0, 2.5, 10.0};
  const std::vector<double> forces{0.032712345678901234, 0.1, 0.98840000000000006};
  writeFemForceCache(m_path, 42, depths, forces);
  std::string why;
  const auto read = readFemForceCache(m_path, 42, {10.0, 1.0}, why);
  ASSERT_TRUE(read.has_value()) << why;
  ASSERT_EQ(read->size(), 2u);
  EXPECT_EQ((*read)[0], forces[2]);
  EXPECT_EQ((*read)[1], forces[0]);
}

TEST_F(FemForceCacheTest, KeepsTheSameInputsOtherDepthsAndDropsAnotherKeys) {
  writeFemForceCache(m_path, 42, {1.0, 10.0}, {0.03, 0.99});
  writeFemForceCache(m_path, 42, {5.0, 10.0}, {0.26, 0.98});
  std::string why;
  const auto read = readFemForceCache(m_path, 42, {1.0, 5.0, 10.0}, why);
  ASSERT_TRUE(read.has_value()) << why;
  EXPECT_EQ(*read, (std::vector<double>{0.03, 0.26, 0.98}));  // 10 mm: the newer force
  writeFemForceCache(m_path, 43, {2.0}, {0.07});
  EXPECT_FALSE(readFemForceCache(m_path, 43, {1.0}, why).has_value());
  EXPECT_TRUE(readFemForceCache(m_path, 43, {2.0}, why).has_value()) << why;
}

TEST_F(FemForceCacheTest, IsNotUsedForOtherInputsOrAMissingDepthOrWhenAbsent) {
  std::string why;
  EXPECT_FALSE(readFemForceCache(m_path, 42, {1.0}, why).has_value());
  EXPECT_NE(why.find("does not exist"), std::string::npos) << why;
  writeFemForceCache(m_path, 42, {1.0, 2.0}, {0.03, 0.07});
  EXPECT_FALSE(readFemForceCache(m_path, 43, {1.0}, why).has_value());
  EXPECT_NE(why.find("other inputs"), std::string::npos) << why;
  EXPECT_FALSE(readFemForceCache(m_path, 42, {1.0, 3.0}, why).has_value());
  EXPECT_NE(why.find("3.0"), std::string::npos) << why;
}

TEST_F(FemForceCacheTest, RefusesAFileThatIsNotOneNamingItsLine) {
  const auto refusal = [&](const std::string& text) {
    write(text);
    std::string why;
    try {
      readFemForceCache(m_path, 42, {1.0}, why);
    } catch (const CommandError& error) {
      return std::string(error.what());
    }
    return std::string("(accepted)");
  };
  const std::string key = "# organ-poke fem reference, key 000000000000002a\n";
  EXPECT_EQ(refusal("depth_mm,fem_force_n\n1,2\n").find(m_path + ":1: expected a first line"), 0u);
  EXPECT_EQ(refusal(key + "depth,force\n").find(m_path + ":2: expected the header"), 0u);
  EXPECT_EQ(refusal(key + "depth_mm,fem_force_n\n1,0.03\n2,nan\n").find(m_path + ":4: expected"),
            0u);
  EXPECT_EQ(refusal(key + "depth_mm,fem_force_n\n1;0.03\n").find(m_path + ":3: expected"), 0u);
  EXPECT_EQ(refusal(key + "depth_mm,fem_force_n\n1,0.03 x\n").find(m_path + ":3: expected"), 0u);
}

}  // namespace
}  // namespace tissuesim::app
