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

}  // namespace tissuesim
