#pragma once
// Stress softening with residual strain (the Mullins effect; Moreno-Guerra et al. 2022,
// Eqs. 16, 17, 19, 20 as corrected in shared/notes/model.md).
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
  double jumpAtPeak = 0.0;      ///< P_s(lambda_max-) - P_v(lambda_max) = R(lambda_max)/lambda_max (Pa); 0 for n = 2
};

class StressSoftening {
 public:
  /// The bracket of Eq. 19 is read in kPa (model.md); this converts it to Pa.
  static constexpr double kResidualStressUnit_Pa = 1000.0;

  explicit StressSoftening(const TissueParameters& parameters);

  /// F(lambda; lambda_max) in (0, 1]; 1 at lambda = lambda_max.
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

  /// The same with its derivative in lambda, given the virgin stress's (Pa). The factor F has a
  /// vertical tangent at lambda_max (model.md); its slope is capped there, at the value
  /// sqrt((M - m) m / M) = 1e-6 would give, so Newton sees a large but finite tangent.
  HermiteNode softenWithSlope(HermiteNode virgin, double lambda, const SofteningPeak& peak) const;
  HermiteNode softenWithSlope(HermiteNode virgin, double lambda, double lambdaMax) const {
    return softenWithSlope(virgin, lambda, peak(lambdaMax));
  }

  bool isEnabled() const { return m_b > 0.0 || m_residualScale_Pa > 0.0; }

 private:
  double m_b;
  double m_residualScale_Pa;  ///< (mu / 2C) * 1 kPa
  int m_exponentN;
};

}  // namespace tissuesim
