// SPDX-License-Identifier: Apache-2.0
#pragma once
// Per-tissue lookup tables, computed once at start-up from the strain energy, for the spring
// force laws of the simulator (Moreno-Guerra et al. 2022, Eqs. 10-12; docs/model.md).
//
//   W_T(lambda)          strain energy density (Pa)                         Eq. 9, uniaxial
//   P(lambda) = W_T'     energy-consistent spring force per unit volume
//                        and unit rest length (Pa): |F| = V_e P(lambda) / L0
//   k_s(lambda)          EESM stiffness function (N):
//                        k_s = 2 v_ij W_T / (lambda^2 - lambda)                       Eq. 11
//
// P and k_s are cubic Hermite splines on one uniform grid over StrainEnergy::usableRange()
// (within [1/3, 3]: a nearly Gaussian tissue locks only far beyond any stretch tissue survives),
// with a node at lambda = 1 exactly, values and slopes taken from the closed forms. The grid
// spacing is 1/20 of the gap between the table's ends and the locking stretches, which keeps
// the relative interpolation error below 1e-6 right up to the ends (the error bound of a
// Hermite cubic near a 1/x pole is (h/x)^4 / 16).
//
// lambda -> 1 is 0/0 in Eq. 11. Writing I1 - 3 = (lambda - 1)^2 (lambda + 2) / lambda and
// W_T = (I1 - 3) Q(I1), Q = integral_0^1 dW_T/dI1(3 + s (I1 - 3)) ds, gives
// k_s = 2 v (lambda - 1)(lambda + 2) Q / lambda^2 with no division by a small number; Q is
// taken by Gauss-Legendre quadrature near I1 = 3. The series is
// k_s = v (3 mu0 e - 5 mu0 e^2 + ...), e = lambda - 1 (tested).

#include "material/StrainEnergy.h"
#include "numerics/UniformHermiteSpline.h"

namespace tissuesim {

class StiffnessTable {
 public:
  /// Tabulates the tissue's energy, stress and stiffness. About 10^4 nodes for the liver.
  explicit StiffnessTable(const StrainEnergy& energy);

  /// The stretches the table covers (StrainEnergy::usableRange(), within [1/3, 3]). Lookups outside
  /// it extrapolate the end cell's cubic: callers must keep lambda inside.
  StretchRange range() const { return m_range; }

  /// W_T (Pa), recovered from k_s by Eq. 11: W_T = k_s (lambda^2 - lambda) / (2 v_ij). A spline
  /// of W_T itself would lose relative accuracy next to rest, where W_T ~ e^2.
  double energy(double lambda) const {
    return m_stiffness.value(lambda) * (lambda * lambda - lambda) * m_halfInverseArea;
  }
  /// P(lambda) = dW_T/dlambda (Pa).
  double stress(double lambda) const { return m_stress.value(lambda); }
  /// P and dP/dlambda of the interpolant (Pa): the spring force and its consistent tangent.
  HermiteNode stressAndSlope(double lambda) const { return m_stress.valueAndSlope(lambda); }
  /// k_s(lambda) of Eq. 11 (N).
  double springStiffness(double lambda) const { return m_stiffness.value(lambda); }
  /// k_s and dk_s/dlambda of the interpolant (N).
  HermiteNode springStiffnessAndSlope(double lambda) const {
    return m_stiffness.valueAndSlope(lambda);
  }

  /// The nodes of the grid (for tests and reports).
  std::size_t nodeCount() const { return m_stress.size(); }
  /// The spline behind stress() (for kernels that evaluate it several springs at a time).
  const UniformHermiteSpline& stressSpline() const { return m_stress; }
  double spacing() const { return m_stress.spacing(); }

  /// k_s and dk_s/dlambda from the closed form, stable through lambda = 1 (N, N).
  static HermiteNode closedFormStiffness(const StrainEnergy& energy, double lambda);

 private:
  StretchRange m_range{};
  double m_halfInverseArea = 0.0;  ///< 1 / (2 v_ij) (1/m^2)
  UniformHermiteSpline m_stress;
  UniformHermiteSpline m_stiffness;
};

}  // namespace tissuesim
