// SPDX-License-Identifier: Apache-2.0
#pragma once
// Small AVX helpers the SIMD kernels share (their callers take the AVX path only where
// numerics/CpuFeatures.h says the CPU has it).

#if defined(__x86_64__)
#include <immintrin.h>

namespace tissuesim {

/// v[0] + v[1] + v[2] + v[3], as (v0 + v2) + (v1 + v3).
__attribute__((target("avx"))) inline double sumOfLanes(__m256d v) {
  const __m128d pair = _mm_add_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
  return _mm_cvtsd_f64(_mm_add_sd(pair, _mm_unpackhi_pd(pair, pair)));
}

}  // namespace tissuesim
#endif
