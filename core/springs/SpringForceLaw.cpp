#include "springs/SpringForceLaw.h"

#include <algorithm>

namespace tissuesim {

SpringForceLaw::SpringForceLaw(SpringLaw law, const StiffnessTable& table,
                               const TissueParameters& parameters, double linearModulus_Pa,
                               bool isSoftening)
    : m_law(law),
      m_table(table),
      m_softening(parameters),
      m_linearModulus_Pa(linearModulus_Pa),
      m_inverseArea(1.0 / parameters.springArea_m2),
      m_isSoftening(isSoftening && law != SpringLaw::Smm && StressSoftening(parameters).isEnabled()),
      m_range(table.range()) {}

SofteningPeak SpringForceLaw::peak(double lambdaMax) const {
  return m_softening.peak(std::min(lambdaMax, m_range.upper));
}

HermiteNode SpringForceLaw::softened(HermiteNode virginStress, double lambda,
                                     const SofteningPeak& peak) const {
  HermiteNode p = m_softening.softenWithSlope(virginStress, lambda, peak);
  const double below = peak.lambdaMax - lambda;
  if (below > 0.0 && below < kJumpBlendWidth && lambda >= 1.0) {
    // Fade the jump out: weight 1 at lambda_max, 0 at lambda_max - width, C1 at both ends.
    const double s = 1.0 - below / kJumpBlendWidth;
    p.value -= peak.jumpAtPeak * s * s * (3.0 - 2.0 * s);
    p.slope -= peak.jumpAtPeak * 6.0 * s * (1.0 - s) / kJumpBlendWidth;
  }
  return p;
}

}  // namespace tissuesim
