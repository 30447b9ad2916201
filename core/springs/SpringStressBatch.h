// SPDX-License-Identifier: Apache-2.0
#pragma once
// The energy-consistent EESM law (eesm) of four springs at once, in AVX registers: the same
// equations as SpringForceLaw::evaluate for stretches inside the usable range,
//
//   P_v = the stress spline at lambda (cubic Hermite, StiffnessTable)
//   P_s = [P_v + R / lambda] F,  F = exp(-b sqrt(q))      (Eqs. 17, 19, 20; StressSoftening)
//   compression after stretching: P_v + P_s(1)
//
// with the slope dP/dlambda when asked. Why: the spring passes are bound by the latency of each
// spring's square roots, division, table loads and exp; four springs per instruction take about
// two thirds of the time of the scalar law compiled for AVX, under half of the SSE2 one
// (prototype over 5k springs, half of them softened: 11 against 18 and 26 ns a spring).
// exp is evaluated here (Cody-Waite reduction, degree-13 Taylor polynomial: within one unit in
// the last place of libm's over [-700, 0], tested), so results differ from the scalar law's in
// the last bits; the force-only and the force-and-stiffness passes both use this one, so they
// agree to the bit.
//
// Not handled here (the caller takes the scalar law for the whole group of four): any stretch
// outside the usable range or at zero length. Units: Pa, as SpringForceLaw. Only where the CPU
// has AVX and FMA (numerics/CpuFeatures.h); SpringForceField decides.

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "springs/SpringForceLaw.h"

namespace tissuesim {

#if defined(__x86_64__)

/// What the batched law reads, taken once from a SpringForceLaw whose law is eesm.
struct SpringStressBatchCoefficients {
  const HermiteNode* nodes;  ///< the stress spline's nodes
  double origin;             ///< its first node's stretch
  double spacing;
  double inverseSpacing;
  double maxCell;  ///< last cell's index (nodes - 2)
  bool isSoftening;
  double b;                 ///< softening's b (Eq. 20)
  double residualScale_Pa;  ///< softening's (mu / 2C) * 1 kPa (Eq. 17)
  // Its onset (StressSoftening.h): q_0, 1 / q_0, sqrt(q_0), 1 / sqrt(q_0).
  double onsetMeasure, inverseOnsetMeasure, rootOnsetMeasure, inverseRootOnsetMeasure;

  explicit SpringStressBatchCoefficients(const SpringForceLaw& law)
      : nodes(law.table().stressSpline().nodes().data()),
        origin(law.table().stressSpline().origin()),
        spacing(law.table().stressSpline().spacing()),
        inverseSpacing(law.table().stressSpline().inverseSpacing()),
        maxCell(static_cast<double>(law.table().stressSpline().size() - 2)),
        isSoftening(law.isSoftening()),
        b(law.softening().b()),
        residualScale_Pa(law.softening().residualScale_Pa()),
        onsetMeasure(law.softening().onsetMeasure()),
        inverseOnsetMeasure(law.softening().inverseOnsetMeasure()),
        rootOnsetMeasure(law.softening().rootOnsetMeasure()),
        inverseRootOnsetMeasure(law.softening().inverseRootOnsetMeasure()) {}
};

namespace batch {

/// exp(x) for x <= 0 (x below -700 gives exp(-700)): x = k ln 2 + r, |r| <= ln 2 / 2, exp(r) by
/// Horner on its degree-13 Taylor polynomial (truncation below 1e-17 relative), times 2^k
/// built in the exponent bits.
__attribute__((target("avx,fma"))) inline __m256d exp(__m256d x) {
  x = _mm256_max_pd(x, _mm256_set1_pd(-700.0));
  const __m256d k =
      _mm256_floor_pd(_mm256_fmadd_pd(x, _mm256_set1_pd(1.4426950408889634), _mm256_set1_pd(0.5)));
  // ln 2 in two parts (Cody-Waite): k * ln2Hi is exact for |k| < 2^11.
  __m256d r = _mm256_fnmadd_pd(k, _mm256_set1_pd(0.693147180369123816490), x);
  r = _mm256_fnmadd_pd(k, _mm256_set1_pd(1.90821492927058770002e-10), r);
  constexpr double kInverseFactorial[14] = {1.0,
                                            1.0,
                                            1.0 / 2,
                                            1.0 / 6,
                                            1.0 / 24,
                                            1.0 / 120,
                                            1.0 / 720,
                                            1.0 / 5040,
                                            1.0 / 40320,
                                            1.0 / 362880,
                                            1.0 / 3628800,
                                            1.0 / 39916800,
                                            1.0 / 479001600,
                                            1.0 / 6227020800.0};
  __m256d p = _mm256_set1_pd(kInverseFactorial[13]);
  for (int i = 12; i >= 0; --i) p = _mm256_fmadd_pd(p, r, _mm256_set1_pd(kInverseFactorial[i]));
  // 2^k: (k + 1023) << 52 as the bits of a double, in two 128-bit halves (AVX has no 256-bit
  // integer shifts).
  const __m128i k32 = _mm256_cvtpd_epi32(k);
  const __m128i bias = _mm_set1_epi64x(1023);
  const __m128i low = _mm_slli_epi64(_mm_add_epi64(_mm_cvtepi32_epi64(k32), bias), 52);
  const __m128i high =
      _mm_slli_epi64(_mm_add_epi64(_mm_cvtepi32_epi64(_mm_srli_si128(k32, 8)), bias), 52);
  const __m256d scale = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_castsi128_pd(low)),
                                             _mm_castsi128_pd(high), 1);
  return _mm256_mul_pd(p, scale);
}

}  // namespace batch

/// stress[k] (and slope[k] when kWithSlope; Pa) of the four springs whose stretches are
/// lambda[0..3] and peaks peaks[0..3] (their lambda_max also in lambdaMax[0..3]). Every stretch
/// must be inside the usable range.
template <bool kWithSlope>
__attribute__((target("avx,fma"))) inline void evaluateStressBatch(
    const SpringStressBatchCoefficients& c, const double* lambda, const double* lambdaMax,
    const SofteningPeak* peaks, double* stress, double* slope) {
  const __m256d l = _mm256_loadu_pd(lambda);
  const __m256d one = _mm256_set1_pd(1.0);
  const __m256d zero = _mm256_setzero_pd();

  __m256d maxima = zero, softened = zero, tension = zero;
  if (c.isSoftening) {
    maxima = _mm256_loadu_pd(lambdaMax);
    // Softening applies below lambda_max on a spring once stretched (StressSoftening's rules).
    softened =
        _mm256_and_pd(_mm256_cmp_pd(maxima, one, _CMP_GT_OQ), _mm256_cmp_pd(l, maxima, _CMP_LT_OQ));
    tension = _mm256_and_pd(softened, _mm256_cmp_pd(l, one, _CMP_GE_OQ));
  }

  // The virgin stress: the spline's cell and the two nodes around it, one 32-byte load per
  // spring, transposed into values and slopes at the cell's ends.
  const __m256d u =
      _mm256_mul_pd(_mm256_sub_pd(l, _mm256_set1_pd(c.origin)), _mm256_set1_pd(c.inverseSpacing));
  const __m256d cell =
      _mm256_min_pd(_mm256_max_pd(_mm256_floor_pd(u), zero), _mm256_set1_pd(c.maxCell));
  const __m256d t = _mm256_sub_pd(u, cell);
  alignas(16) int index[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(index), _mm256_cvttpd_epi32(cell));
  const __m256d n0 = _mm256_loadu_pd(&c.nodes[index[0]].value);
  const __m256d n1 = _mm256_loadu_pd(&c.nodes[index[1]].value);
  const __m256d n2 = _mm256_loadu_pd(&c.nodes[index[2]].value);
  const __m256d n3 = _mm256_loadu_pd(&c.nodes[index[3]].value);
  const __m256d v01 = _mm256_unpacklo_pd(n0, n1);  // (a0, a1, b0, b1) values
  const __m256d s01 = _mm256_unpackhi_pd(n0, n1);  // slopes
  const __m256d v23 = _mm256_unpacklo_pd(n2, n3);
  const __m256d s23 = _mm256_unpackhi_pd(n2, n3);
  const __m256d av = _mm256_permute2f128_pd(v01, v23, 0x20);
  const __m256d bv = _mm256_permute2f128_pd(v01, v23, 0x31);
  const __m256d as = _mm256_permute2f128_pd(s01, s23, 0x20);
  const __m256d bs = _mm256_permute2f128_pd(s01, s23, 0x31);
  const __m256d t2 = _mm256_mul_pd(t, t);
  const __m256d t3 = _mm256_mul_pd(t2, t);
  const __m256d h = _mm256_set1_pd(c.spacing);
  const __m256d two = _mm256_set1_pd(2.0);
  const __m256d three = _mm256_set1_pd(3.0);
  // h00 = 2t^3 - 3t^2 + 1, h10 = t^3 - 2t^2 + t, h01 = 3t^2 - 2t^3, h11 = t^3 - t^2.
  const __m256d h00 = _mm256_add_pd(_mm256_fmsub_pd(two, t3, _mm256_mul_pd(three, t2)), one);
  const __m256d h10 = _mm256_add_pd(_mm256_fnmadd_pd(two, t2, t3), t);
  const __m256d h01 = _mm256_fnmadd_pd(two, t3, _mm256_mul_pd(three, t2));
  const __m256d h11 = _mm256_sub_pd(t3, t2);
  __m256d value = _mm256_fmadd_pd(h00, av, _mm256_mul_pd(h01, bv));
  value = _mm256_fmadd_pd(_mm256_mul_pd(h10, h), as, value);
  value = _mm256_fmadd_pd(_mm256_mul_pd(h11, h), bs, value);
  __m256d valueSlope = zero;
  if constexpr (kWithSlope) {
    // (6t^2 - 6t) / h (a - b) + (3t^2 - 4t + 1) a' + (3t^2 - 2t) b'
    const __m256d six = _mm256_set1_pd(6.0);
    const __m256d g =
        _mm256_mul_pd(_mm256_mul_pd(six, _mm256_sub_pd(t2, t)), _mm256_set1_pd(c.inverseSpacing));
    valueSlope = _mm256_mul_pd(g, _mm256_sub_pd(av, bv));
    valueSlope = _mm256_fmadd_pd(
        _mm256_add_pd(_mm256_fnmadd_pd(_mm256_set1_pd(4.0), t, _mm256_mul_pd(three, t2)), one), as,
        valueSlope);
    valueSlope =
        _mm256_fmadd_pd(_mm256_fnmadd_pd(two, t, _mm256_mul_pd(three, t2)), bs, valueSlope);
  }

  if (_mm256_movemask_pd(softened) != 0) {
    const __m256d inverseMeasure = _mm256_set_pd(peaks[3].inverseMeasure, peaks[2].inverseMeasure,
                                                 peaks[1].inverseMeasure, peaks[0].inverseMeasure);
    const __m256d axial =
        _mm256_set_pd(peaks[3].axial, peaks[2].axial, peaks[1].axial, peaks[0].axial);
    const __m256d lateral =
        _mm256_set_pd(peaks[3].lateral, peaks[2].lateral, peaks[1].lateral, peaks[0].lateral);
    const __m256d offset = _mm256_set_pd(peaks[3].offsetAtRest, peaks[2].offsetAtRest,
                                         peaks[1].offsetAtRest, peaks[0].offsetAtRest);
    const __m256d scale = _mm256_set1_pd(c.residualScale_Pa);
    const __m256d four = _mm256_set1_pd(4.0);
    const __m256d inverse = _mm256_div_pd(one, l);
    const __m256d l2 = _mm256_mul_pd(l, l);
    const __m256d inverse2 = _mm256_mul_pd(inverse, inverse);
    // R = s [ -4 l^2 (A - l^2) + 4 / l (B - 1 / l) ]                                  (Eq. 17)
    const __m256d residual = _mm256_mul_pd(
        scale, _mm256_fmadd_pd(_mm256_mul_pd(four, inverse), _mm256_sub_pd(lateral, inverse),
                               _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(-4.0), l2),
                                             _mm256_sub_pd(axial, l2))));
    const __m256d total = _mm256_fmadd_pd(residual, inverse, value);  // T = P_v + R / lambda
    // m = sqrt(l^4 + 2 / l^2), q = (1 - m / M) m, F = exp(-b sqrt(q))                 (Eq. 20)
    const __m256d m = _mm256_sqrt_pd(_mm256_fmadd_pd(l2, l2, _mm256_mul_pd(two, inverse2)));
    const __m256d q =
        _mm256_max_pd(zero, _mm256_mul_pd(_mm256_fnmadd_pd(m, inverseMeasure, one), m));
    // sqrt(q), or below the onset q_0 its quadratic sqrt(q_0) t (3 - t) / 2, t = q / q_0.
    const __m256d onsetT = _mm256_mul_pd(q, _mm256_set1_pd(c.inverseOnsetMeasure));
    const __m256d inOnset = _mm256_cmp_pd(q, _mm256_set1_pd(c.onsetMeasure), _CMP_LT_OQ);
    const __m256d rootQ = _mm256_blendv_pd(
        _mm256_sqrt_pd(q),
        _mm256_mul_pd(_mm256_set1_pd(c.rootOnsetMeasure),
                      _mm256_mul_pd(onsetT, _mm256_fnmadd_pd(_mm256_set1_pd(0.5), onsetT,
                                                             _mm256_set1_pd(1.5)))),
        inOnset);
    const __m256d f = batch::exp(_mm256_mul_pd(_mm256_set1_pd(-c.b), rootQ));
    const __m256d softenedValue = _mm256_mul_pd(total, f);
    // The n = 1 jump faded out within kJumpBlendWidth below lambda_max (SpringForceLaw):
    // s = 1 - below / width, P -= J s^2 (3 - 2s), P' -= J 6 s (1 - s) / width.
    const __m256d width = _mm256_set1_pd(SpringForceLaw::kJumpBlendWidth);
    const __m256d below = _mm256_sub_pd(maxima, l);
    const __m256d inBlend = _mm256_and_pd(tension, _mm256_cmp_pd(below, width, _CMP_LT_OQ));
    __m256d jump = zero, fade = zero;
    if (_mm256_movemask_pd(inBlend) != 0) {
      jump = _mm256_and_pd(inBlend, _mm256_set_pd(peaks[3].jumpAtPeak, peaks[2].jumpAtPeak,
                                                  peaks[1].jumpAtPeak, peaks[0].jumpAtPeak));
      fade = _mm256_sub_pd(one, _mm256_div_pd(below, width));
      value = _mm256_blendv_pd(value, softenedValue, tension);
      value = _mm256_fnmadd_pd(
          jump, _mm256_mul_pd(_mm256_mul_pd(fade, fade), _mm256_fnmadd_pd(two, fade, three)),
          value);
    } else {
      value = _mm256_blendv_pd(value, softenedValue, tension);
    }
    const __m256d compression = _mm256_andnot_pd(tension, softened);
    if constexpr (kWithSlope) {
      // dR/dlambda = s [ -8 l A + 16 l^3 - 4 B / l^2 + 8 / l^3 ]
      const __m256d residualSlope = _mm256_mul_pd(
          scale, _mm256_add_pd(
                     _mm256_fmsub_pd(_mm256_set1_pd(16.0), _mm256_mul_pd(l2, l),
                                     _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(8.0), l), axial)),
                     _mm256_fmsub_pd(_mm256_set1_pd(8.0), _mm256_mul_pd(inverse2, inverse),
                                     _mm256_mul_pd(_mm256_mul_pd(four, lateral), inverse2))));
      const __m256d dTotal =
          _mm256_fnmadd_pd(residual, inverse2, _mm256_fmadd_pd(residualSlope, inverse, valueSlope));
      // dF/dlambda = -b F (1 - 2 m / M) 2 (l^3 - l^-3) rho'(q) / m, rho' = 1 / (2 max(1e-6,
      // sqrt q)) (the exact law's cap, as StressSoftening's) or (3/2 - t) / sqrt(q_0) below q_0.
      const __m256d dqTimesM = _mm256_mul_pd(
          _mm256_mul_pd(_mm256_fnmadd_pd(_mm256_mul_pd(two, m), inverseMeasure, one), two),
          _mm256_sub_pd(_mm256_mul_pd(l2, l), _mm256_mul_pd(inverse2, inverse)));
      const __m256d rootSlope = _mm256_blendv_pd(
          _mm256_div_pd(_mm256_set1_pd(0.5), _mm256_max_pd(_mm256_set1_pd(1e-6), rootQ)),
          _mm256_mul_pd(_mm256_sub_pd(_mm256_set1_pd(1.5), onsetT),
                        _mm256_set1_pd(c.inverseRootOnsetMeasure)),
          inOnset);
      const __m256d df = _mm256_div_pd(
          _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(-c.b), f), _mm256_mul_pd(dqTimesM, rootSlope)),
          m);
      const __m256d softenedSlope = _mm256_fmadd_pd(total, df, _mm256_mul_pd(dTotal, f));
      valueSlope = _mm256_blendv_pd(valueSlope, softenedSlope, tension);
      // jump is zero outside the blend: these lanes are unchanged.
      valueSlope = _mm256_fnmadd_pd(
          _mm256_mul_pd(jump, _mm256_set1_pd(6.0 / SpringForceLaw::kJumpBlendWidth)),
          _mm256_mul_pd(fade, _mm256_sub_pd(one, fade)), valueSlope);
    }
    value = _mm256_blendv_pd(value, _mm256_add_pd(value, offset), compression);
  }
  _mm256_storeu_pd(stress, value);
  if constexpr (kWithSlope) _mm256_storeu_pd(slope, valueSlope);
}

#endif  // __x86_64__

}  // namespace tissuesim
