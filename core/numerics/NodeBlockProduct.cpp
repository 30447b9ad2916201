// SPDX-License-Identifier: Apache-2.0
#include "numerics/NodeBlockProduct.h"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <cstring>

#include "numerics/AvxLanes.h"
#include "numerics/CpuFeatures.h"

namespace tissuesim {
namespace {

/// A node with more neighbours than this (the liver's most is 27) takes the plain loop, not the
/// gathered one, whose buffer is on the stack.
constexpr int kMaxGatheredNeighbours = 96;

/// The plain loop over one row's blocks.
void multiplyRowScalar(const NodeBlockRows& rows, Eigen::Index j, const double* x, double* y) {
  const int first = rows.neighbourStart[j];
  const int count = rows.neighbourStart[j + 1] - first;
  const Eigen::Index n = 3 * static_cast<Eigen::Index>(count);
  const double* column = rows.values + rows.outer[3 * j];
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0;
    for (int p = 0; p < count; ++p) {
      const double* xi = x + 3 * static_cast<Eigen::Index>(rows.neighbourIndex[first + p]);
      const double* entry = column + c * n + 3 * p;
      sum += entry[0] * xi[0] + entry[1] * xi[1] + entry[2] * xi[2];
    }
    y[3 * j + c] = sum;
  }
}

/// g = j's neighbours' x, 3 per neighbour, then three zeros; returns 3 n_j.
inline Eigen::Index gather(const NodeBlockRows& rows, Eigen::Index j, const double* x, double* g) {
  const int first = rows.neighbourStart[j];
  const int count = rows.neighbourStart[j + 1] - first;
  for (int p = 0; p < count; ++p) {
    std::memcpy(g + 3 * p, x + 3 * static_cast<Eigen::Index>(rows.neighbourIndex[first + p]),
                3 * sizeof(double));
  }
  const Eigen::Index n = 3 * static_cast<Eigen::Index>(count);
  g[n] = g[n + 1] = g[n + 2] = 0.0;
  return n;
}

bool isGathered(const NodeBlockRows& rows, Eigen::Index j) {
  return rows.neighbourStart[j + 1] - rows.neighbourStart[j] <= kMaxGatheredNeighbours;
}

}  // namespace

#if defined(__x86_64__)

namespace {

/// The walk both kernels share: per row, the plain loop past the gather buffer, else the
/// neighbours' x gathered and dotColumns(first column, 3 n_j, g, y_j) for the three rows.
template <void (*dotColumns)(const double*, Eigen::Index, const double*, double*)>
void multiplyRows(const NodeBlockRows& rows, Eigen::Index begin, Eigen::Index end, const double* x,
                  double* y) {
  alignas(32) double g[3 * kMaxGatheredNeighbours + 4];
  for (Eigen::Index j = begin; j < end; ++j) {
    if (!isGathered(rows, j)) {
      multiplyRowScalar(rows, j, x, y);
      continue;
    }
    const Eigen::Index n = gather(rows, j, x, g);
    dotColumns(rows.values + rows.outer[3 * j], n, g, y + 3 * j);
  }
}

/// y[c] = column c . g for the three consecutive columns of length n at `column`, two at a time.
void dotColumnsSse2(const double* column, Eigen::Index n, const double* g, double* y) {
  const double* c0 = column;
  const double* c1 = c0 + n;
  const double* c2 = c1 + n;
  __m128d a0 = _mm_setzero_pd(), a1 = _mm_setzero_pd(), a2 = _mm_setzero_pd();
  Eigen::Index k = 0;
  for (; k + 2 <= n; k += 2) {
    const __m128d gk = _mm_load_pd(g + k);
    a0 = _mm_add_pd(a0, _mm_mul_pd(_mm_loadu_pd(c0 + k), gk));
    a1 = _mm_add_pd(a1, _mm_mul_pd(_mm_loadu_pd(c1 + k), gk));
    a2 = _mm_add_pd(a2, _mm_mul_pd(_mm_loadu_pd(c2 + k), gk));
  }
  if (k < n) {  // n odd: the last product alone (the column's next value is another's)
    const __m128d gk = _mm_load_sd(g + k);
    a0 = _mm_add_pd(a0, _mm_mul_pd(_mm_load_sd(c0 + k), gk));
    a1 = _mm_add_pd(a1, _mm_mul_pd(_mm_load_sd(c1 + k), gk));
    a2 = _mm_add_pd(a2, _mm_mul_pd(_mm_load_sd(c2 + k), gk));
  }
  y[0] = _mm_cvtsd_f64(_mm_add_sd(a0, _mm_unpackhi_pd(a0, a0)));
  y[1] = _mm_cvtsd_f64(_mm_add_sd(a1, _mm_unpackhi_pd(a1, a1)));
  y[2] = _mm_cvtsd_f64(_mm_add_sd(a2, _mm_unpackhi_pd(a2, a2)));
}

/// The same four at a time with FMA (g is 32-byte aligned and zero past n).
__attribute__((target("avx,fma"))) void dotColumnsAvxFma(const double* column, Eigen::Index n,
                                                         const double* g, double* y) {
  // Lane masks for the last 1 to 3 values of a column.
  alignas(32) static constexpr long long kFirstLanes[4][4] = {
      {0, 0, 0, 0}, {-1, 0, 0, 0}, {-1, -1, 0, 0}, {-1, -1, -1, 0}};
  const double* c0 = column;
  const double* c1 = c0 + n;
  const double* c2 = c1 + n;
  __m256d a0 = _mm256_setzero_pd(), a1 = _mm256_setzero_pd(), a2 = _mm256_setzero_pd();
  Eigen::Index k = 0;
  for (; k + 4 <= n; k += 4) {
    const __m256d gk = _mm256_load_pd(g + k);
    a0 = _mm256_fmadd_pd(_mm256_loadu_pd(c0 + k), gk, a0);
    a1 = _mm256_fmadd_pd(_mm256_loadu_pd(c1 + k), gk, a1);
    a2 = _mm256_fmadd_pd(_mm256_loadu_pd(c2 + k), gk, a2);
  }
  if (k < n) {
    // Masked loads: nothing past the column is read (it may be the end of the array).
    const __m256i mask = _mm256_load_si256(reinterpret_cast<const __m256i*>(kFirstLanes[n - k]));
    const __m256d gk = _mm256_load_pd(g + k);  // zero past n
    a0 = _mm256_fmadd_pd(_mm256_maskload_pd(c0 + k, mask), gk, a0);
    a1 = _mm256_fmadd_pd(_mm256_maskload_pd(c1 + k, mask), gk, a1);
    a2 = _mm256_fmadd_pd(_mm256_maskload_pd(c2 + k, mask), gk, a2);
  }
  y[0] = sumOfLanes(a0);
  y[1] = sumOfLanes(a1);
  y[2] = sumOfLanes(a2);
}

}  // namespace

void multiplyNodeRowsSse2(const NodeBlockRows& rows, Eigen::Index begin, Eigen::Index end,
                          const double* x, double* y) {
  multiplyRows<dotColumnsSse2>(rows, begin, end, x, y);
}

void multiplyNodeRowsAvxFma(const NodeBlockRows& rows, Eigen::Index begin, Eigen::Index end,
                            const double* x, double* y) {
  multiplyRows<dotColumnsAvxFma>(rows, begin, end, x, y);
}

#else  // not x86-64: the plain loop for both

void multiplyNodeRowsSse2(const NodeBlockRows& rows, Eigen::Index begin, Eigen::Index end,
                          const double* x, double* y) {
  for (Eigen::Index j = begin; j < end; ++j) multiplyRowScalar(rows, j, x, y);
}
void multiplyNodeRowsAvxFma(const NodeBlockRows& rows, Eigen::Index begin, Eigen::Index end,
                            const double* x, double* y) {
  multiplyNodeRowsSse2(rows, begin, end, x, y);
}

#endif

void multiplyNodeRows(const NodeBlockRows& rows, Eigen::Index begin, Eigen::Index end,
                      const double* x, double* y) {
  if (hasAvxAndFma()) {
    multiplyNodeRowsAvxFma(rows, begin, end, x, y);
  } else {
    multiplyNodeRowsSse2(rows, begin, end, x, y);
  }
}

}  // namespace tissuesim
