// SPDX-License-Identifier: Apache-2.0
#include "fem/IsochoricMaterialPoint.h"

#include <cmath>

#include <Eigen/LU>

namespace tissuesim {

IsochoricResponse evaluateIsochoric(const StrainEnergy& energy, const Eigen::Matrix3d& f,
                                    bool withTangent) {
  IsochoricResponse response;
  const double j = f.determinant();
  if (!(j > 0.0)) return response;
  const double i1 = f.squaredNorm();
  const double scale = std::pow(j, -2.0 / 3.0);  // J^(-2/3)
  const double shift = scale * i1 - 3.0;         // I1bar - 3
  const double chainLimit =
      3.0 * energy.parameters().chainSegmentsN * std::pow(1.0 - StrainEnergy::kLockingMargin, 2.0);
  if (!(shift + 3.0 < chainLimit)) return response;
  const EnergyInI1 w = energy.atInvariantShift(std::max(shift, 0.0));
  const Eigen::Matrix3d inverseTranspose = f.inverse().transpose();
  const Eigen::Matrix3d a = scale * (2.0 * f - (2.0 / 3.0) * i1 * inverseTranspose);
  response.isAdmissible = true;
  response.energy_Pa = w.energy;
  response.stress_Pa = w.dEnergy * a;
  if (!withTangent) return response;
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) {
      // dA along the unit dF = e_k e_l^T.
      const double traceInverse = inverseTranspose(k, l);  // F^-T : dF
      const double traceF = f(k, l);                       // F : dF
      Eigen::Matrix3d dF = Eigen::Matrix3d::Zero();
      dF(k, l) = 1.0;
      const Eigen::Matrix3d dA =
          scale * (-(2.0 / 3.0) * traceInverse * (2.0 * f - (2.0 / 3.0) * i1 * inverseTranspose) +
                   2.0 * dF - (4.0 / 3.0) * traceF * inverseTranspose +
                   (2.0 / 3.0) * i1 * inverseTranspose * dF.transpose() * inverseTranspose);
      const Eigen::Matrix3d dP = w.d2Energy * a(k, l) * a + w.dEnergy * dA;
      for (int i = 0; i < 3; ++i) {
        for (int jj = 0; jj < 3; ++jj) response.tangent_Pa(3 * i + jj, 3 * k + l) = dP(i, jj);
      }
    }
  }
  return response;
}

}  // namespace tissuesim
