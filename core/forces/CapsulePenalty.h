// SPDX-License-Identifier: Apache-2.0
#pragma once
// A rigid capsule (a probe: the segment from tip centre a to b, radius R) pushing points of a
// surface out of it by a penalty on each one's penetration, for static indentation tests on
// either model (the spring network through ForceField, the FEM through FemExtraEnergy). Point p
// is carried by up to three nodes, s_p = sum_k w_pk x_k (a node alone, or a point of a surface
// triangle, as the simulator's contacts on its drawn surface are):
//
//   g_p = |s_p - c_p| - R   (c_p the closest point of the segment),   active when g_p < 0
//   E = sum_p k_p e(g_p),   f_k = -w_pk k_p e'(g_p) n_p,   K_kl = w_pk w_pl k_p e''(g_p) n_p n_p^T
//
// e(g) = g^2 / 2 in contact, made twice differentiable over the first micrometre (a cubic), so
// the stiffness has no jump where a point comes into contact (Newton stalled on such jumps).
//
// k_p = (pressure stiffness, Pa/m) x the point's share of the surface (m^2), so the penalty does
// not depend on how finely the surface is sampled. K is the Gauss-Newton part (PSD); the exact
// Hessian's curvature term k g / d (I - n n^T), negative while pressing, is left out. A point's
// nodes must be joined by springs (a triangle's corners are) for the assembled matrix.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "forces/FemExtraEnergy.h"
#include "forces/ForceField.h"
#include "forces/SmoothedPenalty.h"

namespace tissuesim {

class CapsulePenalty final : public ForceField, public FemExtraEnergy {
 public:
  /// A point: its nodes (an unused slot repeats the first, weight 0), weights (summing to 1)
  /// and stiffness k_p (N/m).
  struct Point {
    std::array<int, 3> nodes{};
    Eigen::Vector3d weights{1.0, 0.0, 0.0};
    double stiffness_N_m = 0.0;
    /// s_p at positions x (3 by #V, m).
    Eigen::Vector3d position(const Eigen::Matrix3Xd& x) const {
      return weights[0] * x.col(nodes[0]) + weights[1] * x.col(nodes[1]) +
             weights[2] * x.col(nodes[2]);
    }
    /// The point's penalty k e(g) along the unit normal n added to its nodes' dE/dx (w_k k e'(g)
    /// n) and Hessian (w_k w_l k e''(g) n n^T) where given (an energy's FemExtraEnergy::add).
    void addPenalty(const PenaltyTerms& terms, const Eigen::Vector3d& n, Eigen::Matrix3Xd* gradient,
                    std::vector<Eigen::Triplet<double>>* hessian) const;
  };

  explicit CapsulePenalty(std::vector<Point> points);

  Eigen::Vector3d tip_m = Eigen::Vector3d::Zero();   ///< a, the hemispherical end's centre
  Eigen::Vector3d top_m = Eigen::Vector3d::UnitZ();  ///< b
  double radius_m = 0.0025;

  /// The force the nodes exert on the capsule at x (N): minus the sum of f_i.
  Eigen::Vector3d reaction(const Eigen::Matrix3Xd& x) const;

  // ForceField.
  const char* name() const override { return "capsule"; }
  double energy(const Eigen::Matrix3Xd& x) const override;
  void addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f, const ForcePass& pass,
                 ForceReport& report) const override;
  void acceptTrialStiffness() const override { m_current ^= 1; }
  void prepareProducts(const PartBounds& bounds) override { m_bounds = bounds; }
  void addStiffnessProduct(int part, const double* x, double* y) const override;
  void addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const override;
  void addStiffness(NodeBlockMatrix& matrix) const override;

  // FemExtraEnergy.
  double add(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient,
             std::vector<Eigen::Triplet<double>>* hessian) const override;

 private:
  /// An active point: its index, k_p e''(g_p) (N/m) and outward normal.
  struct Active {
    int point;
    double stiffness_N_m;
    Eigen::Vector3d n;
  };
  /// The gap g of a position and the unit normal n there.
  double gap(const Eigen::Vector3d& s, Eigen::Vector3d& n) const;

  std::vector<Point> m_points;
  mutable std::array<std::vector<Active>, 2> m_slots;
  mutable int m_current = 0;
  PartBounds m_bounds{};
};

}  // namespace tissuesim
