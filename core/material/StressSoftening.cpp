// SPDX-License-Identifier: Apache-2.0
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

StressSoftening::StressSoftening(const TissueParameters& parameters, double onsetMeasure)
    : m_b(parameters.softeningB),
      m_residualScale_Pa(parameters.mu_Pa / (2.0 * parameters.softeningC_Pa) *
                         kResidualStressUnit_Pa),
      m_exponentN(parameters.softeningExponentN),
      m_onsetMeasure(std::max(0.0, onsetMeasure)),
      m_inverseOnsetMeasure(m_onsetMeasure > 0.0 ? 1.0 / m_onsetMeasure : 0.0),
      m_rootOnsetMeasure(std::sqrt(m_onsetMeasure)),
      m_inverseRootOnsetMeasure(m_onsetMeasure > 0.0 ? 1.0 / m_rootOnsetMeasure : 0.0) {}

double StressSoftening::factor(double lambda, double lambdaMax) const {
  const double m = stretchMeasure(lambda);
  // M is m at lambda_max (model.md's fix of Eq. 20's typo).
  const double bigM = stretchMeasure(lambdaMax);
  const double argument = std::max(0.0, (bigM - m) * m / bigM);
  return std::exp(-m_b * rootOfMeasure<false>(argument).value);
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

}  // namespace tissuesim
