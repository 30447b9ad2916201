// SPDX-License-Identifier: Apache-2.0
#pragma once
// Stress softening with residual strain (the Mullins effect; Moreno-Guerra et al. 2022,
// Eqs. 16, 17, 19, 20 as corrected in docs/model.md).
//
// On unloading from the largest stretch reached, lambda_max, the engineering stress of a law
// whose virgin stress is P_v(lambda) becomes
//
//   P_s = [ P_v(lambda) + R(lambda) / lambda ] * F(lambda),                   (Eqs. 19, 21)
//   F   = exp(-b sqrt((M - m) m / M)),  m = sqrt(lambda^4 + 2 lambda^-2),  M = m(lambda_max)
//   R   = (mu / 2C) (lambda_1 g_1 - lambda_3 g_3) * 1 kPa,
//         lambda_k g_k = -4 lambda_k^2 (lambda_max,k^n - lambda_k^2)                (Eq. 17)
//
// with the uniaxial stretches lambda_1 = lambda, lambda_3 = lambda^-1/2. (For the energy-
// consistent law P_v(lambda) = Phi (lambda^2 - 1/lambda) / lambda, Phi = 2 dW_T/dI1, which is
// model.md's sigma_s exactly.) The bracket mu/(2C)(...) is dimensionless as printed and is read
// in kPa, as model.md says; R is converted to Pa here.
//
// Rules:
//  - lambda >= lambda_max, or lambda_max <= 1 (never stretched): the virgin curve.
//  - 1 <= lambda < lambda_max: P_s above. It reaches zero at a residual stretch > 1.
//  - lambda < 1 with lambda_max > 1 (compression after stretching; outside the paper, which
//    tests tension only): P_v(lambda) + P_s(1), so the stress is continuous at lambda = 1 and
//    the residual offset carries into compression. This is our extension, not the paper's.
//  - lambda_max only grows (MullinsState), until an explicit reset.
//
// The onset (for the solvers; the reference curves keep the exact law): F leaves lambda_max with
// a vertical tangent, sqrt(q) having none at q = 0. A spring at its peak (where every loading
// spring sits after each step's commit) then has, just below it, a stiffness without bound, and
// a Newton step that unloads it by a hair meets a stress drop its tangent did not foresee. With
// an onset q_0 > 0, sqrt(q) is replaced below q_0 by the quadratic that meets it C1 there,
//
//   rho(q) = sqrt(q_0) t (3 - t) / 2,  t = q / q_0            (rho(0) = 0: F = 1 at the peak)
//
// so the tangent at the peak is finite, 3 / (2 sqrt(q_0)) in q. rho <= sqrt(q), so the stress
// there is at most exp(0.1741 b sqrt(q_0)) - 1 above the exact law (the largest of
// sqrt(t) - t (3 - t) / 2 on [0, 1] is 0.17404), and equal to it from q_0 on.

#include <algorithm>
#include <cmath>

#include "material/TissueParameters.h"
#include "numerics/UniformHermiteSpline.h"

namespace tissuesim {

/// The memory of the Mullins effect for one spring or specimen: the largest stretch reached.
class MullinsState {
 public:
  double lambdaMax() const { return m_lambdaMax; }
  /// Records a stretch; lambda_max never decreases.
  void observe(double lambda) {
    if (lambda > m_lambdaMax) m_lambdaMax = lambda;
  }
  void reset() { m_lambdaMax = 1.0; }

 private:
  double m_lambdaMax = 1.0;
};

/// What softening needs of a spring's peak stretch, computed once when the peak changes
/// rather than in every force evaluation.
struct SofteningPeak {
  double lambdaMax = 1.0;
  double inverseMeasure = 0.0;  ///< 1 / M, M = m(lambda_max) (Eq. 20)
  double axial = 1.0;           ///< lambda_max^n
  double lateral = 1.0;         ///< lambda_max,3^n = lambda_max^(-n/2)
  double offsetAtRest = 0.0;    ///< P_s(1) = R(1) F(1) (Pa), the compression branch's offset
  /// P_s(lambda_max-) - P_v(lambda_max) = R(lambda_max) / lambda_max (Pa); 0 for n = 2.
  double jumpAtPeak = 0.0;
};

class StressSoftening {
 public:
  /// The bracket of Eq. 19 is read in kPa (model.md); this converts it to Pa.
  static constexpr double kResidualStressUnit_Pa = 1000.0;

  /// @param onsetMeasure q_0 >= 0 of the rounded onset (see the header); 0 is the exact law.
  explicit StressSoftening(const TissueParameters& parameters, double onsetMeasure = 0.0);

  /// F(lambda; lambda_max) in (0, 1], with the onset if one is set; 1 at lambda = lambda_max.
  double factor(double lambda, double lambdaMax) const;

  /// R(lambda; lambda_max) in Pa (negative below lambda_max for lambda > 1: the permanent set).
  double residualStress(double lambda, double lambdaMax) const;

  /// The quantities of a peak stretch lambda_max (>= 1).
  SofteningPeak peak(double lambdaMax) const;

  /// The softened engineering stress (Pa) of a law with virgin stress `virginStress` (Pa) at
  /// `lambda`, following the rules above.
  double soften(double virginStress, double lambda, double lambdaMax) const {
    return softenWithSlope({virginStress, 0.0}, lambda, peak(lambdaMax)).value;
  }

  /// The same with its derivative in lambda, given the virgin stress's (Pa). With the exact law
  /// (no onset) F has a vertical tangent at lambda_max (model.md); its slope is capped there, at
  /// the value sqrt((M - m) m / M) = 1e-6 would give.
  /// Inline: it runs once per softened spring per force evaluation (a third of the explicit
  /// slab's spring pass when it was a call).
  /// kWithSlope false: the value alone (slope 0), the same to the bit; for passes that need
  /// forces only (a third fewer operations on this branch, and one division fewer).
  template <bool kWithSlope = true>
  HermiteNode softenWithSlope(HermiteNode virgin, double lambda, const SofteningPeak& peak) const {
    if (peak.lambdaMax <= 1.0 || lambda >= peak.lambdaMax) return virgin;
    // Compression after stretching: carry the offset P_s(1) so the curve stays continuous.
    if (lambda < 1.0) return {virgin.value + peak.offsetAtRest, virgin.slope};

    // T = P_v + R / lambda;  P_s = T F;  P_s' = T' F + T F'.
    const double inverse = 1.0 / lambda;
    const double l2 = lambda * lambda;
    const double inverse2 = inverse * inverse;
    // R = s [ -4 l^2 (A - l^2) + 4 / l (B - 1 / l) ]                                 (Eq. 17)
    const double residual = m_residualScale_Pa * (-4.0 * l2 * (peak.axial - l2) +
                                                  4.0 * inverse * (peak.lateral - inverse));
    const double t = virgin.value + residual * inverse;

    // F = exp(-b sqrt(q)), q = (M - m) m / M;  dq/dlambda = (M - 2 m) m' / M,
    // m' = 2 (lambda^3 - lambda^-3) / m;  dF/dlambda = -b F dq / (2 sqrt(q)).
    const double m = std::sqrt(l2 * l2 + 2.0 * inverse2);
    const double q = std::max(0.0, (1.0 - m * peak.inverseMeasure) * m);
    const RootOfMeasure root = rootOfMeasure<kWithSlope>(q);
    const double f = std::exp(-m_b * root.value);
    if constexpr (!kWithSlope) {
      return {t * f, 0.0};
    } else {
      // dR/dlambda = s [ -8 l A + 16 l^3 - 4 B / l^2 + 8 / l^3 ]
      const double residualSlope =
          m_residualScale_Pa * (-8.0 * lambda * peak.axial + 16.0 * l2 * lambda -
                                4.0 * peak.lateral * inverse2 + 8.0 * inverse2 * inverse);
      const double dt = virgin.slope + residualSlope * inverse - residual * inverse2;
      const double dqTimesM =
          (1.0 - 2.0 * m * peak.inverseMeasure) * 2.0 * (l2 * lambda - inverse2 * inverse);
      const double df = -m_b * f * dqTimesM * root.slope / m;
      return {t * f, dt * f + t * df};
    }
  }
  HermiteNode softenWithSlope(HermiteNode virgin, double lambda, double lambdaMax) const {
    return softenWithSlope(virgin, lambda, peak(lambdaMax));
  }

  /// sqrt(q) of F = exp(-b sqrt(q)) (Eq. 20), or below the onset its quadratic (see the
  /// header), and its derivative in q. With the exact law that derivative is capped where
  /// sqrt(q) = 1e-6: at the peak itself it has no value.
  struct RootOfMeasure {
    double value;
    double slope;
  };
  template <bool kWithSlope = true>
  RootOfMeasure rootOfMeasure(double q) const {
    if (q < m_onsetMeasure) {
      const double t = q * m_inverseOnsetMeasure;
      return {m_rootOnsetMeasure * (t * (1.5 - 0.5 * t)),
              kWithSlope ? (1.5 - t) * m_inverseRootOnsetMeasure : 0.0};
    }
    constexpr double kMinRoot = 1e-6;
    const double value = std::sqrt(q);
    return {value, kWithSlope ? 0.5 / std::max(kMinRoot, value) : 0.0};
  }

  bool isEnabled() const { return m_b > 0.0 || m_residualScale_Pa > 0.0; }
  /// q_0 of the onset and its derived numbers (1 / q_0, sqrt(q_0), 1 / sqrt(q_0); all 0 for the
  /// exact law), for kernels that evaluate several springs at a time.
  double onsetMeasure() const { return m_onsetMeasure; }
  double inverseOnsetMeasure() const { return m_inverseOnsetMeasure; }
  double rootOnsetMeasure() const { return m_rootOnsetMeasure; }
  double inverseRootOnsetMeasure() const { return m_inverseRootOnsetMeasure; }
  /// b of F (Eq. 20) and (mu / 2C) * 1 kPa of R (Eq. 17), for kernels that evaluate
  /// softenWithSlope several springs at a time.
  double b() const { return m_b; }
  double residualScale_Pa() const { return m_residualScale_Pa; }

 private:
  double m_b;
  double m_residualScale_Pa;  ///< (mu / 2C) * 1 kPa
  int m_exponentN;
  double m_onsetMeasure;
  double m_inverseOnsetMeasure;
  double m_rootOnsetMeasure;
  double m_inverseRootOnsetMeasure;
};

}  // namespace tissuesim
