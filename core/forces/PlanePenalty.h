// SPDX-License-Identifier: Apache-2.0
#pragma once
// A rigid plane (a tray: up . y >= h) under surface points, as an energy the FEM adds to its own
// (FemExtraEnergy): point p, carried by up to three nodes (s_p = sum_k w_pk x_k), is pushed
// up by a penalty on its penetration,
//
//   g_p = up . s_p - h,   E = sum_p k_p e(g_p),   f_k = -w_pk k_p e'(g_p) up,
//   K_kl = w_pk w_pl k_p e''(g_p) up up^T
//
// with e the penalty smoothed over its first micrometre (SmoothedPenalty.h), and k_p = (pressure
// stiffness, Pa/m) x the point's share of the surface (m^2), as the spring network's tray
// (sim/TraySupport.h) takes it. Frictionless. Shapes: x 3 by #V (m), gradient 3 by #V (N).

#include <vector>

#include <Eigen/Core>

#include "forces/CapsulePenalty.h"
#include "forces/FemExtraEnergy.h"

namespace tissuesim {

class PlanePenalty final : public FemExtraEnergy {
 public:
  /// up: the plane's normal (normalised here). @throws std::invalid_argument on a zero or
  /// non-finite normal or height.
  PlanePenalty(std::vector<CapsulePenalty::Point> points, const Eigen::Vector3d& up,
               double height_m);

  /// The force the plane exerts on the points at x (N): what it carries.
  Eigen::Vector3d support_N(const Eigen::Matrix3Xd& x) const;
  /// The deepest point below the plane at x (m; 0 when none is).
  double maxPenetration_m(const Eigen::Matrix3Xd& x) const;

  double add(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient,
             std::vector<Eigen::Triplet<double>>* hessian) const override;

 private:
  std::vector<CapsulePenalty::Point> m_points;
  Eigen::Vector3d m_up;
  double m_height_m;
};

}  // namespace tissuesim
