// SPDX-License-Identifier: Apache-2.0
#include "analysis/GoodnessOfFit.h"

#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

TEST(GoodnessOfFit, PerfectMatchIsOne) {
  const std::vector<double> y = {1, 2, 4, 8};
  EXPECT_DOUBLE_EQ(coefficientOfDetermination(y, y), 1.0);
}

TEST(GoodnessOfFit, KnownValue) {
  // mean 2.5, SS_tot = 5, SS_res = 0.25 + 0 + 0 + 0.25 -> R^2 = 0.9
  const std::vector<double> y = {1, 2, 3, 4};
  const std::vector<double> m = {1.5, 2, 3, 3.5};
  EXPECT_NEAR(coefficientOfDetermination(y, m), 0.9, 1e-15);
  // Predicting the mean gives 0; worse than the mean is negative.
  EXPECT_NEAR(coefficientOfDetermination(y, std::vector<double>(4, 2.5)), 0.0, 1e-15);
  EXPECT_LT(coefficientOfDetermination(y, std::vector<double>{4, 3, 2, 1}), 0.0);
}

TEST(GoodnessOfFit, SlopeThroughOrigin) {
  const std::vector<double> x = {1, 2, 3};
  const std::vector<double> y = {2, 4.5, 5.5};  // sum xy = 27.5, sum xx = 14
  EXPECT_NEAR(slopeThroughOrigin(x, y), 27.5 / 14.0, 1e-15);
}

TEST(GoodnessOfFit, RejectsMismatchedInput) {
  const std::vector<double> a = {1, 2};
  const std::vector<double> b = {1};
  EXPECT_THROW(coefficientOfDetermination(a, b), std::invalid_argument);
  EXPECT_THROW(slopeThroughOrigin(a, b), std::invalid_argument);
  EXPECT_THROW(slopeThroughOrigin(std::vector<double>{0, 0}, a), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
