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

double StressSoftening::soften(double virginStress, double lambda, double lambdaMax) const {
  if (lambdaMax <= 1.0 || lambda >= lambdaMax) return virginStress;
  if (lambda >= 1.0) {
    return (virginStress + residualStress(lambda, lambdaMax) / lambda) * factor(lambda, lambdaMax);
  }
  // Compression after stretching: carry the offset P_s(1) so the curve stays continuous.
  return virginStress + residualStress(1.0, lambdaMax) * factor(1.0, lambdaMax);
}

HermiteNode StressSoftening::softenWithSlope(HermiteNode virgin, double lambda,
                                             double lambdaMax) const {
  if (lambdaMax <= 1.0 || lambda >= lambdaMax) return virgin;
  if (lambda < 1.0) {
    return {virgin.value + residualStress(1.0, lambdaMax) * factor(1.0, lambdaMax), virgin.slope};
  }
  // T = P_v + R / lambda;  P_s = T F;  P_s' = T' F + T F'.
  const double maxAxial = m_exponentN == 2 ? lambdaMax * lambdaMax : lambdaMax;
  const double maxLateral = m_exponentN == 2 ? 1.0 / lambdaMax : 1.0 / std::sqrt(lambdaMax);
  const double l2 = lambda * lambda;
  const double residual = residualStress(lambda, lambdaMax);
  // dR/dlambda = s [ -8 lambda A + 16 lambda^3 - 4 B / lambda^2 + 8 / lambda^3 ]
  const double residualSlope =
      m_residualScale_Pa *
      (-8.0 * lambda * maxAxial + 16.0 * l2 * lambda - 4.0 * maxLateral / l2 + 8.0 / (l2 * lambda));
  const double t = virgin.value + residual / lambda;
  const double dt = virgin.slope + residualSlope / lambda - residual / l2;

  const double m = stretchMeasure(lambda);
  const double bigM = stretchMeasure(lambdaMax);
  const double f = factor(lambda, lambdaMax);
  // q = (M - m) m / M; dq/dlambda = (M - 2 m) m' / M, m' = 2 (lambda^3 - lambda^-3) / m.
  constexpr double kMinRootQ = 1e-6;
  const double rootQ = std::max(kMinRootQ, std::sqrt(std::max(0.0, (bigM - m) * m / bigM)));
  const double dm = 2.0 * (l2 * lambda - 1.0 / (l2 * lambda)) / m;
  const double dq = (bigM - 2.0 * m) * dm / bigM;
  const double df = -m_b * f * dq / (2.0 * rootQ);
  return {t * f, dt * f + t * df};
}

}  // namespace tissuesim
