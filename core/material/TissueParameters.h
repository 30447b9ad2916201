// SPDX-License-Identifier: Apache-2.0
#pragma once
// The parameters of one tissue, in SI units inside the engine.
//
// The tissue file gives moduli in kPa (the paper's unit); TissueFile converts them to Pa at the
// boundary, so every field here is SI. Symbols follow Moreno-Guerra et al. 2022 (Eqs. 2-20).

#include <string>

namespace tissuesim {

/// How beta = L^-1(lambda_r) is computed in W_iso (Eq. 3).
enum class InverseLangevin {
  Puso,   ///< beta = 3 r / (1 - r^3), Eq. 7 (the paper's choice, the default)
  Exact,  ///< Newton solve of coth(beta) - 1/beta = r to machine precision
};

struct TissueParameters {
  std::string name;    ///< free text, shown in reports
  std::string source;  ///< where the values come from (citation)

  // Strain energy W_T = (1 - f) W_iso + f W_aniso (Eqs. 2, 3, 8).
  double mu_Pa = 0.0;           ///< network modulus mu (> 0)
  double chainSegmentsN = 0.0;  ///< N, segments per chain; locking needs N > 1
  double A1_Pa = 0.0;           ///< fibre term, linear in (I1 - 3) (>= 0)
  double A2_Pa = 0.0;           ///< fibre term, quadratic in (I1 - 3) (>= 0)
  double fibreFraction = 0.0;   ///< f in [0, 1], volume fraction of the fibre term

  // Stress softening with residual strain (Eqs. 16-20).
  double softeningB = 0.0;     ///< b (dimensionless, >= 0); 0 turns softening off
  double softeningC_Pa = 0.0;  ///< C (> 0); the residual term scales with mu / (2 C)
  int softeningExponentN = 1;  ///< n in g_k (Eq. 17): 1 (the paper's) or 2

  // The EESM spring (Eq. 11) and the mass of the tissue.
  double springArea_m2 = 0.0;     ///< v_ij, the specimen cross-section of the fit (m^2)
  double density_kg_m3 = 1060.0;  ///< mass density (liver about 1060 kg/m^3)

  // The session assessment's damage threshold (sim/SessionAssessment.h): a spring stretched to
  // this is counted as damaged tissue. The default is the liver capsule's ultimate local strain
  // one standard deviation below its mean, 47 +- 29 % (Brunon, Bruyere-Garnier and Coret 2010,
  // J. Biomech. 43:2221, uniaxial tension of human and porcine capsule to failure; the specimen
  // preparation the paper follows): the strain at which about one capsule in six has torn.
  double damageStretch = 1.18;  ///< > 1 (dimensionless)

  InverseLangevin inverseLangevin = InverseLangevin::Puso;
};

}  // namespace tissuesim
