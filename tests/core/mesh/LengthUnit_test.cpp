// SPDX-License-Identifier: Apache-2.0
// Guessing a mesh file's unit from its size: the one that makes it an organ's.

#include "mesh/LengthUnit.h"

#include <string>

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

TEST(LengthUnit, TheUnitThatMakesAnOrgansSizeIsChosen) {
  EXPECT_EQ(std::string(guessLengthUnit(153.0).symbol), "mm");  // a liver exported in mm
  EXPECT_EQ(std::string(guessLengthUnit(21.0).symbol), "cm");
  EXPECT_EQ(std::string(guessLengthUnit(0.2).symbol), "m");
  // The boundaries lie at the geometric means: 0.15 m x sqrt(10) between cm and mm units.
  EXPECT_EQ(std::string(guessLengthUnit(47.0).symbol), "cm");
  EXPECT_EQ(std::string(guessLengthUnit(48.0).symbol), "mm");
  EXPECT_DOUBLE_EQ(guessLengthUnit(153.0).metresPerUnit, 0.001);
}

}  // namespace
}  // namespace tissuesim
