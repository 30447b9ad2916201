// SPDX-License-Identifier: Apache-2.0
#pragma once
// The Langevin function L(beta) = coth(beta) - 1/beta and its inverse, as used by the
// non-Gaussian chain network of Eqs. 3-7 (Moreno-Guerra et al. 2022).
//
// Each function returns beta together with its first two derivatives in r = L(beta), which the
// strain energy needs for the analytic stress (Eq. 13) and its tangent.

namespace tissuesim {

/// beta(r) and its derivatives d beta / dr, d^2 beta / dr^2, for 0 < r < 1 (dimensionless).
struct InverseLangevinValue {
  double beta;
  double dBeta;
  double d2Beta;
};

/// L(beta) = coth(beta) - 1/beta, stable for small and large beta (beta >= 0).
double langevin(double beta);

/// L'(beta) = 1/beta^2 - 1/sinh^2(beta), stable for small and large beta (beta >= 0).
double langevinSlope(double beta);

/// Puso's approximation beta = 3 r / (1 - r^3) (Eq. 7) with its derivatives. Needs 0 <= r < 1.
InverseLangevinValue inverseLangevinPuso(double r);

/// The exact inverse: Newton on L(beta) = r from Puso's value, to machine precision.
/// Needs 0 <= r < 1.
InverseLangevinValue inverseLangevinExact(double r);

/// ln(sinh(beta)) without overflow for large beta (beta > 0).
double logSinh(double beta);

}  // namespace tissuesim
