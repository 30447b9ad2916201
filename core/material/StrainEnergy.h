// SPDX-License-Identifier: Apache-2.0
#pragma once
// The strain energy density W_T of the tissue (Moreno-Guerra et al. 2022, Eqs. 2-9) and the
// uniaxial engineering stress derived from it (Eqs. 13, 18, 21, as corrected in
// docs/model.md).
//
//   W_T     = (1 - f) W_iso + f W_aniso                                            (Eq. 2)
//   W_iso   = mu [ N (beta r + ln(beta / sinh beta)) - ln(beta / r) ] + c,
//             r = sqrt(I1 / 3) / sqrt(N),  beta = L^-1(r)                   (Eqs. 3-7)
//   W_aniso = A1/3 (I1 - 3) + A2/9 (I1 - 3)^2 - (2 A1 / 3) ln sqrt(I3)              (Eq. 8)
//
// The material is incompressible (I3 = 1), so W_T depends on I1 alone; c makes W_T(I1 = 3) = 0.
// Uniaxial kinematics: lambda_1 = lambda, lambda_2 = lambda_3 = lambda^-1/2,
// I1 = lambda^2 + 2 / lambda, and the engineering stress is P = dW_T / dlambda, coded
// analytically through I1 (it equals (T1 - T3) / lambda of Eq. 13 with T3 = 0).
//
// Units: energies and stresses in Pa (= J/m^3), stretches dimensionless.
//
// The model has no value once r >= 1 (chain locking): in uniaxial extension that is outside
// the roots of lambda^3 - 3 N lambda + 2 = 0 (about 0.62 < lambda < 1.50 for the porcine liver).
// Nothing here is evaluated outside; callers check `lockingRange()` or `usableRange()`.

#include "material/TissueParameters.h"
#include "numerics/UniformHermiteSpline.h"

namespace tissuesim {

/// A closed interval of stretches [lower, upper] (dimensionless).
struct StretchRange {
  double lower;
  double upper;
  bool contains(double lambda) const { return lambda >= lower && lambda <= upper; }
};

/// W_T and its first two derivatives in I1 (all in Pa).
struct EnergyInI1 {
  double energy;
  double dEnergy;   ///< dW_T/dI1; Phi = 2 dW_T/dI1 in the softening law (Eq. 19)
  double d2Energy;  ///< d^2 W_T / dI1^2
};

/// Q(I1) = W_T / (I1 - 3), the secant of W_T from rest, and dQ/dI1 (Pa). Finite at I1 = 3,
/// where Q = dW_T/dI1 = mu0 / 2.
struct SecantFromRest {
  double value;
  double slope;
};

/// W_T, P = dW_T/dlambda and dP/dlambda in uniaxial extension (all in Pa).
struct UniaxialResponse {
  double energy;
  double stress;
  double stressSlope;
};

class StrainEnergy {
 public:
  /// The gap to locking kept by `usableRange()`: r <= 1 - kLockingMargin.
  static constexpr double kLockingMargin = 1e-3;

  explicit StrainEnergy(const TissueParameters& parameters);

  /// W_T as a function of I1 (I3 = 1). Needs 3 <= I1 < 3 N (r < 1).
  /// Near rest the closed form of W_T loses digits (W_iso's constant c is ~10^3 Pa while W_T is
  /// ~mu0 e^2), so there W_T = (I1 - 3) Q is used, Q from secantFromRest().
  EnergyInI1 inI1(double firstInvariant) const { return atInvariantShift(firstInvariant - 3.0); }
  /// The same as a function of I1 - 3, which callers near rest should compute without
  /// cancellation (see invariantShift()).
  EnergyInI1 atInvariantShift(double shift) const;

  /// dW_T/dI1 and d2W_T/dI1^2 alone at shift = I1 - 3 (energy left 0): what a force pass
  /// needs, without the quadrature that the energy takes near rest.
  EnergyInI1 slopesAtInvariantShift(double shift) const {
    return closedFormAtShift(shift, /*withEnergy=*/false);
  }
  /// Q = W_T / (I1 - 3) and dQ/dI1 at shift = I1 - 3, with no division by a small number: for
  /// |shift| < 1e-2, Q = integral_0^1 dW_T/dI1(3 + s shift) ds by 8-point Gauss-Legendre.
  SecantFromRest secantFromRest(double shift) const;

  /// Uniaxial energy, stress and stress slope at stretch lambda (inside lockingRange()).
  UniaxialResponse uniaxial(double lambda) const;
  double energy(double lambda) const { return uniaxial(lambda).energy; }
  double stress(double lambda) const { return stressAndSlope(lambda).value; }
  /// P and dP/dlambda only (Pa): cheaper than uniaxial(), which also integrates the energy.
  HermiteNode stressAndSlope(double lambda) const;

  /// The stretches at which r = 1 (the model's locking; open at both ends).
  StretchRange lockingRange() const { return m_locking; }
  /// The stretches at which r <= 1 - kLockingMargin: where tables and simulations may go.
  StretchRange usableRange() const { return m_usable; }
  /// The largest I1 - 3 in that usable range (any deformation, not only uniaxial): where the
  /// FEM's isochoric energy stops.
  double usableInvariantShift() const { return m_usableShift; }

  /// mu0 = 2 dW_T/dI1 at I1 = 3: the small-strain shear modulus (Pa). Young's modulus is 3 mu0.
  double initialShearModulus() const { return m_initialShearModulus; }

  const TissueParameters& parameters() const { return m_parameters; }

  /// I1 = lambda^2 + 2 / lambda (uniaxial, incompressible).
  static double firstInvariant(double lambda) { return lambda * lambda + 2.0 / lambda; }
  /// I1 - 3 = (lambda - 1)^2 (lambda + 2) / lambda, exact near lambda = 1.
  static double invariantShift(double lambda) {
    return (lambda - 1.0) * (lambda - 1.0) * (lambda + 2.0) / lambda;
  }
  /// dI1/dlambda = 2 lambda - 2 / lambda^2 = 2 (lambda - 1)(lambda^2 + lambda + 1) / lambda^2.
  static double invariantSlope(double lambda) {
    return 2.0 * (lambda - 1.0) * (lambda * lambda + lambda + 1.0) / (lambda * lambda);
  }

  /// Stretches where lambda^2 + 2/lambda = 3 K, i.e. the roots of lambda^3 - 3 K lambda + 2,
  /// for K > 1 (one root below 1, one above).
  static StretchRange stretchesAtInvariant(double invariantOverThree);

 private:
  /// W_T by its closed form (digits lost near rest) with its first two derivatives in I1, at
  /// shift = I1 - 3. The energy (three logarithms) is skipped, and left 0, unless asked for.
  EnergyInI1 closedFormAtShift(double shift, bool withEnergy) const;
  /// W_iso without its constant c, and its first two derivatives in r.
  EnergyInI1 isotropicInChainStretch(double r, bool withEnergy) const;

  TissueParameters m_parameters;
  double m_isoConstant = 0.0;  ///< c of Eq. 3 (Pa)
  double m_initialShearModulus = 0.0;
  StretchRange m_locking{};
  StretchRange m_usable{};
  double m_usableShift = 0.0;
};

}  // namespace tissuesim
