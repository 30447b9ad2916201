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
// Left out: the residual strain of Eq. 17. The paper states it as uniaxial stress offsets along
// the stretch and across it; an energy of I1bar alone, isotropic in the deformation's
// directions, has no permanent set to carry it.

#include "material/StressSoftening.h"

namespace tissuesim {

/// A material point's peak: I_p - 3 and what softening needs of it, made once when it rises.
struct IsochoricPeak {
  double shift = 0.0;           ///< I_p - 3 (0: never strained, the virgin curve everywhere)
  double inverseMeasure = 0.0;  ///< 1 / M (unused while shift is 0)
};

/// The uniaxial stretch lambda >= 1 with lambda^2 + 2 / lambda = 3 + shift (shift >= 0).
double uniaxialStretchOfShift(double shift);

/// The peak at I1bar - 3 = shift (>= 0).
IsochoricPeak isochoricPeak(double shift);

/// F in (0, 1] at I1bar - 3 = shift under `peak` (1 at or past it).
double isochoricSofteningFactor(const StressSoftening& softening, double shift,
                                const IsochoricPeak& peak);

}  // namespace tissuesim
