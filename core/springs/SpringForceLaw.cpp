// SPDX-License-Identifier: Apache-2.0
#include "springs/SpringForceLaw.h"

#include <algorithm>

namespace tissuesim {

const char* springLawName(SpringLaw law) {
  switch (law) {
    case SpringLaw::Eesm:
      return "eesm";
    case SpringLaw::EesmPaper:
      return "eesm-paper";
    case SpringLaw::Smm:
      return "smm";
  }
  return "eesm";
}

std::optional<SpringLaw> springLawNamed(std::string_view name) {
  for (const SpringLaw law : {SpringLaw::Eesm, SpringLaw::EesmPaper, SpringLaw::Smm}) {
    if (name == springLawName(law)) return law;
  }
  return std::nullopt;
}

SpringForceLaw::SpringForceLaw(SpringLaw law, const StiffnessTable& table,
                               const TissueParameters& parameters, double linearModulus_Pa,
                               bool isSoftening)
    : m_law(law),
      m_table(table),
      m_softening(parameters, kSofteningOnsetMeasure),
      m_linearModulus_Pa(linearModulus_Pa),
      m_inverseArea(1.0 / parameters.springArea_m2),
      m_isSoftening(isSoftening && law != SpringLaw::Smm &&
                    StressSoftening(parameters).isEnabled()),
      m_range(table.range()) {}

SofteningPeak SpringForceLaw::peak(double lambdaMax) const {
  return m_softening.peak(std::min(lambdaMax, m_range.upper));
}

}  // namespace tissuesim
