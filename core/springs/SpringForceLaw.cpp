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
      m_isSoftening(isSoftening && law != SpringLaw::Smm &&
                    StressSoftening(parameters).isEnabled()),
      m_range(table.range()) {}

SofteningPeak SpringForceLaw::peak(double lambdaMax) const {
  return m_softening.peak(std::min(lambdaMax, m_range.upper));
}

}  // namespace tissuesim
