// SPDX-License-Identifier: Apache-2.0
#pragma once
// The tissue's isochoric strain energy at one material point, as the FEM evaluates it:
//
//   W(F) = W_T(I1bar),   I1bar = J^(-2/3) tr(F^T F),   J = det F                    (Pa)
//   P = dW/dF = W_T'(I1bar) A,   A = dI1bar/dF = J^(-2/3) (2 F - 2/3 I1 F^-T)           (Pa)
//   dP/dF = W_T'' A (x) A + W_T' dA/dF                                      (9 by 9, Pa)
//
// W_T(I1) is the tissue file's energy (StrainEnergy, Eqs. 2-9), incompressible there and so a
// function of I1 alone: evaluated at I1bar it is the isochoric part of a nearly incompressible
// continuum, whose volumetric part the FEM adds per element (FemModel). The 9 by 9 tangent's
// index of F_iJ is 3 i + J.
//
// No value (isAdmissible false) where J <= 0 or past the usable range of the chain model
// (r = sqrt(I1bar / 3N) > 1 - StrainEnergy::kLockingMargin).

#include <Eigen/Core>

#include "material/StrainEnergy.h"

namespace tissuesim {

using StressTangent = Eigen::Matrix<double, 9, 9>;

struct IsochoricResponse {
  bool isAdmissible = false;
  double energy_Pa = 0.0;
  Eigen::Matrix3d stress_Pa = Eigen::Matrix3d::Zero();  ///< P, first Piola-Kirchhoff
  StressTangent tangent_Pa = StressTangent::Zero();     ///< dP/dF, when asked for
};

/// W, P and, when `withTangent`, dP/dF at F.
IsochoricResponse evaluateIsochoric(const StrainEnergy& energy, const Eigen::Matrix3d& f,
                                    bool withTangent);
/// The same for W_T's value and slopes at F's I1bar given (`w`: a softened point's,
/// fem/IsochoricSoftening.h), at an F that is admissible (det F > 0, within the usable range).
IsochoricResponse evaluateIsochoric(const Eigen::Matrix3d& f, const EnergyInI1& w,
                                    bool withTangent);
/// I1bar - 3 = J^(-2/3) tr(F^T F) - 3 at F (det F > 0).
double isochoricShift(const Eigen::Matrix3d& f);

/// dP/dF at F (det F > 0) with its negative eigenvalues set to zero, for W' = dW_T/dI1bar and
/// W'' = d2W_T/dI1bar2 (Pa) given: in closed form, from F's singular values sigma (F = U S V^T),
/// as the tangent of an isotropic energy decomposes (Teran et al. 2005; Smith, de Goes and Kim
/// 2019). With Psi_i = dW/dsigma_i = W' s (2 sigma_i - 2/3 I1 / sigma_i), s = J^(-2/3):
///
///   twist modes U (e_i e_j^T - e_j e_i^T) V^T / sqrt 2:  (Psi_i + Psi_j) / (sigma_i + sigma_j)
///                                                      = W' s (2 - 2/3 I1 / (sigma_i sigma_j))
///   flip modes  U (e_i e_j^T + e_j e_i^T) V^T / sqrt 2:  (Psi_i - Psi_j) / (sigma_i - sigma_j)
///                                                      = W' s (2 + 2/3 I1 / (sigma_i sigma_j))
///   scaling modes U diag(q) V^T, q the eigenvectors of d2W/dsigma_i dsigma_j (3x3).
///
/// No division by sigma_i - sigma_j: equal singular values (rest) are no special case. A 9x9
/// eigensolver per element cost several times the rest of a real-time force pass.
StressTangent projectedIsochoricTangent(const Eigen::Matrix3d& f, double dEnergy, double d2Energy);

/// W_T and its slopes at I1bar - 3 = shift, continued linearly in I1bar past `limitShift` (the
/// end of the usable range), so an element driven past locking still gets a finite restoring
/// force; below 0 (rounding at rest) W_T's value at 0. The energy itself only when `withEnergy`
/// (a force pass needs the slopes alone).
EnergyInI1 continuedIsochoricEnergy(const StrainEnergy& energy, double shift, double limitShift,
                                    bool withEnergy);

/// The exact dP/dF = W_T'' A (x) A + W_T' d2I1bar/dF2 at F (det F > 0), the latter
///   J^(-2/3) [2 I - 4/3 (F (x) H + H (x) F) + 4/9 I1 H (x) H + 2/3 I1 H_iL H_kJ],
/// H = F^-T, in closed form: the same as evaluateIsochoric's, whose loop over unit dF it avoids.
/// `a` = A, `i1` = tr(F^T F), `scale` = J^(-2/3), `w` W_T's slopes at I1bar.
StressTangent exactIsochoricTangent(const Eigen::Matrix3d& f, const Eigen::Matrix3d& a, double i1,
                                    double scale, const EnergyInI1& w);

}  // namespace tissuesim
