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

HermiteNode SpringForceLaw::virgin(double lambda) const {
  switch (m_law) {
    case SpringLaw::Eesm:
      return m_table.stressAndSlope(lambda);
    case SpringLaw::EesmPaper: {
      const HermiteNode k = m_table.springStiffnessAndSlope(lambda);
      return {k.value * lambda * m_inverseArea, (k.slope * lambda + k.value) * m_inverseArea};
    }
    case SpringLaw::Smm:
      return {m_linearModulus_Pa * (lambda - 1.0), m_linearModulus_Pa};
  }
  return {0.0, 0.0};
}

SofteningPeak SpringForceLaw::peak(double lambdaMax) const {
  return m_softening.peak(std::min(lambdaMax, m_range.upper));
}

SpringStress SpringForceLaw::evaluate(double lambda, const SofteningPeak& peak) const {
  if (m_law == SpringLaw::Smm) {
    return {m_linearModulus_Pa * (lambda - 1.0), m_linearModulus_Pa, false};
  }
  const double clamped = std::clamp(lambda, m_range.lower, m_range.upper);
  HermiteNode p = virgin(clamped);
  if (m_isSoftening) {
    p = m_softening.softenWithSlope(p, clamped, peak);
    const double below = peak.lambdaMax - clamped;
    if (below > 0.0 && below < kJumpBlendWidth && clamped >= 1.0) {
      // Fade the jump out: weight 1 at lambda_max, 0 at lambda_max - width, C1 at both ends.
      const double s = 1.0 - below / kJumpBlendWidth;
      p.value -= peak.jumpAtPeak * s * s * (3.0 - 2.0 * s);
      p.slope -= peak.jumpAtPeak * 6.0 * s * (1.0 - s) / kJumpBlendWidth;
    }
  }
  if (clamped != lambda) {
    // Linear continuation past the usable range: the barrier (see the header).
    return {p.value + p.slope * (lambda - clamped), p.slope, true};
  }
  return {p.value, p.slope, false};
}

}  // namespace tissuesim
