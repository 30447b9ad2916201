#include "material/StressSoftening.h"

#include <algorithm>
#include <cmath>

namespace tissuesim {
namespace {
/// m = sqrt(lambda^4 + 2 lambda^-2) of Eq. 20.
double stretchMeasure(double lambda) {
  const double l2 = lambda * lambda;
  return std::sqrt(l2 * l2 + 2.0 / l2);
}
}  // namespace

StressSoftening::StressSoftening(const TissueParameters& parameters)
    : m_b(parameters.softeningB),
      m_residualScale_Pa(parameters.mu_Pa / (2.0 * parameters.softeningC_Pa) *
                         kResidualStressUnit_Pa),
      m_exponentN(parameters.softeningExponentN) {}

double StressSoftening::factor(double lambda, double lambdaMax) const {
  const double m = stretchMeasure(lambda);
  // M is m at lambda_max (model.md's fix of Eq. 20's typo).
  const double bigM = stretchMeasure(lambdaMax);
  const double argument = std::max(0.0, (bigM - m) * m / bigM);
  return std::exp(-m_b * std::sqrt(argument));
}

double StressSoftening::residualStress(double lambda, double lambdaMax) const {
  const double maxAxial = m_exponentN == 2 ? lambdaMax * lambdaMax : lambdaMax;
  // lambda_max,3^n = (lambda_max^-1/2)^n
  const double maxLateral = m_exponentN == 2 ? 1.0 / lambdaMax : 1.0 / std::sqrt(lambdaMax);
  const double l2 = lambda * lambda;
  const double lateral2 = 1.0 / lambda;  // lambda_3^2
  const double axialTerm = -4.0 * l2 * (maxAxial - l2);
  const double lateralTerm = -4.0 * lateral2 * (maxLateral - lateral2);
  return m_residualScale_Pa * (axialTerm - lateralTerm);
}

SofteningPeak StressSoftening::peak(double lambdaMax) const {
  SofteningPeak p;
  p.lambdaMax = lambdaMax;
  p.inverseMeasure = 1.0 / stretchMeasure(lambdaMax);
  p.axial = m_exponentN == 2 ? lambdaMax * lambdaMax : lambdaMax;
  p.lateral = m_exponentN == 2 ? 1.0 / lambdaMax : 1.0 / std::sqrt(lambdaMax);
  p.offsetAtRest = lambdaMax > 1.0 ? residualStress(1.0, lambdaMax) * factor(1.0, lambdaMax) : 0.0;
  p.jumpAtPeak = lambdaMax > 1.0 ? residualStress(lambdaMax, lambdaMax) / lambdaMax : 0.0;
  return p;
}

HermiteNode StressSoftening::softenWithSlope(HermiteNode virgin, double lambda,
                                             const SofteningPeak& peak) const {
  if (peak.lambdaMax <= 1.0 || lambda >= peak.lambdaMax) return virgin;
  // Compression after stretching: carry the offset P_s(1) so the curve stays continuous.
  if (lambda < 1.0) return {virgin.value + peak.offsetAtRest, virgin.slope};

  // T = P_v + R / lambda;  P_s = T F;  P_s' = T' F + T F'.
  const double inverse = 1.0 / lambda;
  const double l2 = lambda * lambda;
  const double inverse2 = inverse * inverse;
  // R = s [ -4 l^2 (A - l^2) + 4 / l (B - 1 / l) ]                                   (Eq. 17)
  const double residual =
      m_residualScale_Pa * (-4.0 * l2 * (peak.axial - l2) + 4.0 * inverse * (peak.lateral - inverse));
  // dR/dlambda = s [ -8 l A + 16 l^3 - 4 B / l^2 + 8 / l^3 ]
  const double residualSlope =
      m_residualScale_Pa * (-8.0 * lambda * peak.axial + 16.0 * l2 * lambda -
                            4.0 * peak.lateral * inverse2 + 8.0 * inverse2 * inverse);
  const double t = virgin.value + residual * inverse;
  const double dt = virgin.slope + residualSlope * inverse - residual * inverse2;

  // F = exp(-b sqrt(q)), q = (M - m) m / M;  dq/dlambda = (M - 2 m) m' / M,
  // m' = 2 (lambda^3 - lambda^-3) / m.
  const double m = std::sqrt(l2 * l2 + 2.0 * inverse2);
  const double q = std::max(0.0, (1.0 - m * peak.inverseMeasure) * m);
  const double rootQ = std::sqrt(q);
  const double f = std::exp(-m_b * rootQ);
  // The tangent is vertical at lambda_max: cap it where sqrt(q) = 1e-6 (see the header).
  constexpr double kMinRootQ = 1e-6;
  const double dm = 2.0 * (l2 * lambda - inverse2 * inverse) / m;
  const double dq = (1.0 - 2.0 * m * peak.inverseMeasure) * dm;
  const double df = -m_b * f * dq / (2.0 * std::max(kMinRootQ, rootQ));
  return {t * f, dt * f + t * df};
}

}  // namespace tissuesim
