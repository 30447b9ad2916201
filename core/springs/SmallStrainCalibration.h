// SPDX-License-Identifier: Apache-2.0
#pragma once
// The spring network's small-strain calibration (docs/model.md, "The spring network"): springs
// that each carry V_e W_T(lambda) give a specimen a small-strain Young's modulus that is not the
// continuum's 3 mu0 (a spring network has no Poisson effect of its own), so every V_e is scaled
// by one factor c that makes it so.
//
// The modulus is the linearised network's at rest, pulled along x by the grips:
//
//   K = c K_springs + K_volume                                            (N/m, 3#V by 3#V)
//   K_springs = sum_e V_e P'(1) / L0^2  n n^T      (a spring at rest carries no force: no
//                                                   geometric part)
//   K_volume  = sum_cells (kappa / V0) g g^T       (the volume term's Hessian, exact at J = 1)
//   K u = 0 on the free DOFs, u_x = L on the moving nodes (unit strain), 0 on the other fixed ones
//   E = (sum over the moving nodes of (K u)_x) / section                                  (Pa)
//
// Springs alone are linear in c: c = target / E(1). With the volume term (which c does not
// scale) E(c) rises monotonically with c, and E(c) = target is solved by secant steps.
// A pure function of the mesh, the law and kappa: one sparse factorisation per step, no state.

#include <vector>

#include "springs/SpringForceLaw.h"
#include "springs/SpringMesh.h"

namespace tissuesim {

/// How a specimen is held for a uniaxial pull along x.
struct UniaxialGrips {
  std::vector<char> isFixed;     ///< 3#V flags of the fixed DOFs, the moving nodes' x among them
  std::vector<int> movingNodes;  ///< moved along x by the specimen's length
  double length_m = 0.0;         ///< along x
  double section_m2 = 0.0;       ///< normal to x
};

/// E (Pa) of the specimen `mesh` (its V_e as given) under `law` at rest, with the volume term of
/// bulkModulus_Pa when > 0. @throws std::invalid_argument when the grips leave it free to move
/// (the linearised system is singular) or the law has no stiffness at rest.
double smallStrainModulus(const SpringMesh& mesh, const SpringForceLaw& law, double bulkModulus_Pa,
                          const UniaxialGrips& grips);

/// The factor c on every V_e of `mesh` for which smallStrainModulus() is targetModulus_Pa
/// (to 1e-10 relative). @throws std::invalid_argument as smallStrainModulus(), or when the volume
/// term alone is already stiffer than the target (no c > 0 reaches it).
double smallStrainStiffnessScale(const SpringMesh& mesh, const SpringForceLaw& law,
                                 double bulkModulus_Pa, const UniaxialGrips& grips,
                                 double targetModulus_Pa);

}  // namespace tissuesim
