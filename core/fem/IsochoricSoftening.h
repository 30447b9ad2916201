// SPDX-License-Identifier: Apache-2.0
#pragma once
// Stress softening (the Mullins effect, Eq. 20 as docs/model.md reads it) at a material point of
// the FEM, whose isochoric energy is W_T(I) of I = I1bar alone: below the point's peak I_p (the
// largest I1bar it has reached) its stress is the virgin one times
//
//   F = exp(-b sqrt(q)),  q = (M - m) m / M,  m = sqrt(lambda^4 + 2 lambda^-2),  M = m(lambda_p)
//
// and at or past it the virgin curve (F = 1). lambda is the uniaxial stretch with the same I1bar,
// lambda^2 + 2 / lambda = I (its root >= 1), so a point in uniaxial tension softens exactly as
// the paper's specimen (Eqs. 19-21 with the residual term R = 0). The onset is rounded as the
// spring law's (StressSoftening's q_0).
//
// With its peak held, the softened point is elastic in I (pseudo-elasticity, Ogden and Roxburgh
// 1999): its stress F W_T' is the slope of
//
//   W_s(I) = W_T(I_p) - integral_I^{I_p} F(I') W_T'(I') dI'   (I < I_p),   W_T(I) at or past it
//
// (C1 at I_p; W_s'' = F W_T'' + F' W_T' >= 0, since F rises to 1 at the peak), so a body whose
// peaks are held settles where a plain energy is least, and its tangent is that energy's.
// The integral is taken by Gauss-Legendre in sqrt(I_p - I) near the peak and in sqrt(I - 3) near
// rest, each side of the rounded onset apart: there the integrand is smooth (in I it has a root's
// steepness at the peak, and the uniaxial stretch one at rest).
//
// Left out: the residual strain of Eq. 17. The paper states it as uniaxial stress offsets along
// the stretch and across it; an energy of I1bar alone, isotropic in the deformation's
// directions, has no permanent set to carry it.

#include "material/StrainEnergy.h"
#include "material/StressSoftening.h"

namespace tissuesim {

/// The rounded onset (StressSoftening's q_0) at the FEM's material points: wider than the spring
/// law's (which an implicit step meets with as many iterations as it takes), so that the FEM at
/// its own rate, one Newton iteration an update, meets a tangent at a peak a third as steep. The
/// stress just below a peak then exceeds the paper's law by at most exp(0.174 b sqrt(q_0)) - 1
/// (StressSoftening.h), about three times the spring law's excess.
inline constexpr double kIsochoricSofteningOnsetMeasure = 1e-3;

/// A material point's peak: I_p - 3 and what softening needs of it, made once when it rises.
struct IsochoricPeak {
  double shift = 0.0;           ///< I_p - 3 (0: never strained, the virgin curve everywhere)
  double inverseMeasure = 0.0;  ///< 1 / M (unused while shift is 0)
  double onsetShift = 0.0;      ///< I - 3 where q = q_0: the rounded onset's start (<= shift)
  double energy_Pa = 0.0;       ///< W_T(I_p) (W_s's value there; isochoricPeak(energy, ...))
};

/// F and dF/dI (at I1bar - 3 = shift).
struct IsochoricSofteningFactor {
  double value = 1.0;
  double slope = 0.0;
};

/// The uniaxial stretch lambda >= 1 with lambda^2 + 2 / lambda = 3 + shift (shift >= 0).
double uniaxialStretchOfShift(double shift);

/// The peak at I1bar - 3 = shift (>= 0), for the factor alone (energy_Pa 0, onsetShift 0).
IsochoricPeak isochoricPeak(double shift);
/// The same with what the softened energy needs: W_T there, and where `softening`'s onset
/// starts.
IsochoricPeak isochoricPeak(const StrainEnergy& energy, const StressSoftening& softening,
                            double shift);

/// F in (0, 1] at I1bar - 3 = shift under `peak` (1 at or past it).
double isochoricSofteningFactor(const StressSoftening& softening, double shift,
                                const IsochoricPeak& peak);
/// The same with its slope in I (0 at or past the peak).
IsochoricSofteningFactor isochoricSofteningFactorWithSlope(const StressSoftening& softening,
                                                           double shift, const IsochoricPeak& peak);

/// W_s, W_s' and W_s'' (Pa) at I1bar - 3 = shift >= 0 under `peak` (made with the energy), given
/// W_T's value and slopes there (`virgin`).
EnergyInI1 softenedIsochoricEnergy(const StrainEnergy& energy, const StressSoftening& softening,
                                   double shift, const IsochoricPeak& peak,
                                   const EnergyInI1& virgin);

}  // namespace tissuesim
