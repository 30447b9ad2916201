// SPDX-License-Identifier: Apache-2.0
#include "springs/SpringStressBatch.h"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "numerics/CpuFeatures.h"

namespace tissuesim {
namespace {

#if defined(__x86_64__)
/// batch::exp over an array, four at a time (the caller has checked for AVX and FMA).
__attribute__((target("avx,fma"))) void batchExp(const std::vector<double>& x,
                                                 std::vector<double>& y) {
  for (std::size_t i = 0; i + 4 <= x.size(); i += 4)
    _mm256_storeu_pd(&y[i], batch::exp(_mm256_loadu_pd(&x[i])));
}
#endif

TEST(SpringStressBatch, ExpIsWithinTwoUlpsOfLibm) {
  // The softening factor F = exp(-b sqrt(q)) of four springs at once: its own exp must be as
  // good as libm's to a unit or two in the last place over the whole range it is used on (x <= 0;
  // below -700 it returns exp(-700), far under any force that matters).
#if defined(__x86_64__)
  if (!hasAvxAndFma())
    GTEST_SKIP() << "this CPU has no AVX with FMA: the batched law is never used";
  std::vector<double> x;
  for (int i = 0; i <= 700000; ++i) x.push_back(-0.001 * i);        // the range, 1e-3 apart
  for (int k = -40; k <= 0; ++k) x.push_back(-std::ldexp(1.0, k));  // near zero
  for (int k = -1000; k >= -1020; --k) x.push_back(k * 0.6931471805599453);  // reduction's edges
  x.push_back(0.0);
  x.push_back(-0.34657359027997264);  // -ln 2 / 2
  while (x.size() % 4 != 0) x.push_back(-1.0);
  std::vector<double> y(x.size());
  batchExp(x, y);
  double worst = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double expected = std::exp(std::max(x[i], -700.0));
    worst = std::max(
        worst, std::abs(y[i] - expected) / (expected * std::numeric_limits<double>::epsilon()));
  }
  EXPECT_LE(worst, 2.0) << "ulps";  // 1.0 measured; a degree-11 polynomial gives 40
  EXPECT_EQ(y[0], 1.0);             // exp(0), exactly
#else
  GTEST_SKIP() << "not an x86-64 build";
#endif
}

}  // namespace
}  // namespace tissuesim
