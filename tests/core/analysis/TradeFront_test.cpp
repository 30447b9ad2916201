// SPDX-License-Identifier: Apache-2.0
// The map's reading: the Pareto front keeps exactly the points nothing beats on both axes, and
// the growth exponent recovers a power law's.

#include "analysis/TradeFront.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

TEST(TradeFront, KeepsThePointsNothingBeatsOnBothAxes) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  //                             0     1     2     3     4     5    6
  const std::vector<double> cost{1.0, 2.0, 2.0, 3.0, 0.5, 4.0, nan};
  const std::vector<double> error{50.0, 20.0, 30.0, 25.0, 80.0, 5.0, 0.0};
  // 2 is beaten by 1 (same cost, less error), 3 by 1 (cheaper and better), 6 has no cost.
  EXPECT_EQ(paretoFront(cost, error), (std::vector<int>{4, 0, 1, 5}));
  EXPECT_TRUE(paretoFront({}, {}).empty());
  EXPECT_THROW(paretoFront({1.0}, {}), std::invalid_argument);
}

TEST(TradeFront, ErrorsWithinTheResolutionAreTiesTheCheaperPointTakes) {
  //                             0      1      2      3
  const std::vector<double> cost{1.0, 2.0, 3.0, 4.0};
  const std::vector<double> error{50.0, 49.8, 49.0, 48.6};
  EXPECT_EQ(paretoFront(cost, error), (std::vector<int>{0, 1, 2, 3}));
  // Within half a point: 1 ties 0; 2 is a point below 0; 3 ties 2.
  EXPECT_EQ(paretoFront(cost, error, 0.5), (std::vector<int>{0, 2}));
}

TEST(TradeFront, TheExponentOfAPowerLaw) {
  const std::vector<double> springs{1000.0, 5300.0, 20000.0, 100000.0};
  std::vector<double> time;
  for (const double n : springs) time.push_back(3e-7 * std::pow(n, 1.15));
  EXPECT_NEAR(powerLawExponent(springs, time), 1.15, 1e-12);
  // Non-positive values are left out; one point left has no slope.
  EXPECT_NEAR(powerLawExponent({1.0, 10.0, -1.0}, {2.0, 20.0, 5.0}), 1.0, 1e-12);
  EXPECT_TRUE(std::isnan(powerLawExponent({1.0, 0.0}, {1.0, 1.0})));
}

}  // namespace
}  // namespace tissuesim
