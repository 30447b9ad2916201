// SPDX-License-Identifier: Apache-2.0
#include "numerics/UniformHermiteSpline.h"

#include <cmath>

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

UniformHermiteSpline tabulate(double (*f)(double), double (*df)(double), double origin,
                              double spacing, int count) {
  std::vector<HermiteNode> nodes;
  for (int i = 0; i < count; ++i) {
    const double x = origin + i * spacing;
    nodes.push_back({f(x), df(x)});
  }
  return UniformHermiteSpline(origin, spacing, nodes);
}

TEST(UniformHermiteSpline, ReproducesCubicsExactly) {
  auto f = [](double x) { return 2 * x * x * x - x * x + 3 * x - 1; };
  auto df = [](double x) { return 6 * x * x - 2 * x + 3; };
  const UniformHermiteSpline spline = tabulate(f, df, -1.0, 0.25, 9);
  for (double x = -1.0; x <= 1.0; x += 0.0371) {
    EXPECT_NEAR(spline.value(x), f(x), 1e-13);
    EXPECT_NEAR(spline.valueAndSlope(x).slope, df(x), 1e-12);
  }
}

TEST(UniformHermiteSpline, ErrorFallsAsTheFourthPowerOfSpacing) {
  auto f = [](double x) { return std::sin(x); };
  auto df = [](double x) { return std::cos(x); };
  double errors[2];
  for (int k = 0; k < 2; ++k) {
    const double h = 0.1 / (1 << k);
    const UniformHermiteSpline spline = tabulate(f, df, 0.0, h, static_cast<int>(2.0 / h) + 1);
    double worst = 0;
    for (double x = 0.0; x < 2.0; x += 0.001)
      worst = std::max(worst, std::abs(spline.value(x) - f(x)));
    errors[k] = worst;
  }
  EXPECT_NEAR(errors[0] / errors[1], 16.0, 2.0);
}

TEST(UniformHermiteSpline, NodesAreHitAndOutsideIsClampedToEndCells) {
  auto f = [](double x) { return std::exp(x); };
  const UniformHermiteSpline spline = tabulate(f, f, 0.0, 0.5, 5);
  EXPECT_DOUBLE_EQ(spline.value(1.0), std::exp(1.0));
  EXPECT_DOUBLE_EQ(spline.value(2.0), std::exp(2.0));
  EXPECT_DOUBLE_EQ(spline.back(), 2.0);
  EXPECT_TRUE(std::isfinite(spline.value(-10.0)));
  EXPECT_TRUE(std::isfinite(spline.value(10.0)));
}

}  // namespace
}  // namespace tissuesim
