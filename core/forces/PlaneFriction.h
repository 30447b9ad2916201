// SPDX-License-Identifier: Apache-2.0
#pragma once
// Coulomb friction between the tissue's surface points and a flat support (the tray), as a
// force field inside the implicit step. Each touching point p is tied to an anchor a_p on the
// plane by a tangential penalty that saturates at Coulomb's limit:
//
//   g_p(x) = P (s_p(x) + d_p - a_p)          slip from the anchor, in the plane (m);
//                                            P = I - n n^T, n the plane's normal
//   E_p = k_p |g|^2 / 2                      |g| <= r_p = L_p / k_p      (stick)
//       = L_p (|g| - r_p / 2)                |g| >  r_p                  (slip)
//   f_p = -k_p g (stick), -L_p g / |g| (slip)   on s_p, reaching node k as w_k f_p (N)
//   K_p = k_p P (stick), (L_p / |g|) b b^T (slip; b = n x g / |g|)      (N/m, PSD)
//
// L_p = mu N_p is the limit from the point's normal force N_p at the last accepted step (the
// normal force lagged one step, as IPC's lagged friction takes it: Li et al. 2020), and k_p the
// support's normal penalty at the point, so a sticking point gives way by at most mu times its
// sink before it slides. s_p = sum_k w_k x_k is the point carried by up to four nodes (the
// weights clamped to the tet that carries it), d_p the gap to the drawn point, frozen for the
// step, as the support's own contacts freeze it. E_p is convex in g (a Huber function), so
// Newton's matrix is exact and PSD: the stick and slip branches are one energy, and a point that
// starts to slide mid-step does so inside the solve, with Coulomb's force, not the step after.
//
// Between steps, acceptStep() applies Coulomb's law to the anchors: a point that slid (|g| > r_p)
// has its anchor dragged to r_p behind it, a point that left the plane loses it, a point that
// came down onto it gets one where it touched. The anchors are the only state; a rejected step
// leaves them as they were.

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products, unitOrthogonal

#include "forces/ForceField.h"
#include "numerics/RankOneTerm.h"
#include "numerics/RankOneTermDiagonals.h"

namespace tissuesim {

/// A point of the tissue's surface, moved by up to four nodes (an unused slot repeats the first,
/// weight 0): `embedded` weights put it where it is drawn (they may extrapolate past the tet
/// that carries it), `carried` (the same clamped to the tet) take the loads back to the nodes.
struct CarriedSurfacePoint {
  std::array<int, kMaxTermNodes> nodes{};
  Eigen::Vector4d embedded = Eigen::Vector4d(1.0, 0.0, 0.0, 0.0);
  Eigen::Vector4d carried = Eigen::Vector4d(1.0, 0.0, 0.0, 0.0);
  double stiffness_N_m = 0.0;  ///< the support's normal penalty at the point (N/m)

  static Eigen::Vector3d at(const CarriedSurfacePoint& point, const Eigen::Vector4d& weights,
                            const Eigen::Matrix3Xd& x) {
    return weights[0] * x.col(point.nodes[0]) + weights[1] * x.col(point.nodes[1]) +
           weights[2] * x.col(point.nodes[2]) + weights[3] * x.col(point.nodes[3]);
  }
  Eigen::Vector3d drawn(const Eigen::Matrix3Xd& x) const { return at(*this, embedded, x); }
  Eigen::Vector3d load(const Eigen::Matrix3Xd& x) const { return at(*this, carried, x); }
};

class PlaneFriction final : public ForceField {
 public:
  /// The plane up . y = height_m (up: unit, out of the support into the tissue); mu the
  /// coefficient of friction (> 0); `points` the surface points that can touch it; #V nodes.
  PlaneFriction(std::vector<CarriedSurfacePoint> points, const Eigen::Vector3d& up, double height_m,
                double coefficient, Eigen::Index nodeCount);

  /// The coming step's friction: each anchored point's tie, its gap to the drawn point frozen
  /// at x (the step's start). No allocation.
  void beginStep(const Eigen::Matrix3Xd& x);
  /// Coulomb's law on the anchors at x, the state an accepted step reached (see the header).
  void acceptStep(const Eigen::Matrix3Xd& x);
  /// No point anchored (nothing touches).
  void releaseAnchors();

  /// The anchors, to keep and put back with a state (reset to the settled start).
  struct Anchor {
    Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  ///< a_p, on the plane
    double limit_N = 0.0;                                  ///< L_p; 0: not anchored
  };
  const std::vector<Anchor>& anchors() const { return m_anchors; }
  void restoreAnchors(const std::vector<Anchor>& anchors);

  /// The friction on the tissue at x, summed over the step's ties (N, in the plane).
  Eigen::Vector3d force_N(const Eigen::Matrix3Xd& x) const;
  /// Ties this step, and how many of them slide at x (|g| > r_p).
  int tieCount() const { return static_cast<int>(m_ties.size()); }
  int slidingCount(const Eigen::Matrix3Xd& x) const;

  // ForceField. K is exact and PSD (a pass's isProjected changes nothing).
  const char* name() const override { return "friction"; }
  double energy(const Eigen::Matrix3Xd& x) const override;
  void addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f, const ForcePass& pass,
                 ForceReport& report) const override;
  void acceptTrialStiffness() const override { m_current ^= 1; }
  void prepareProducts(const PartBounds& bounds) override { m_bounds = bounds; }
  void addStiffnessProduct(int part, const double* x, double* y) const override;
  void addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const override;
  void addStiffness(NodeBlockMatrix& matrix) const override;

 private:
  /// A tied point this step: which one, and its slip's constant part P (d_p - a_p).
  struct Tie {
    int point;
    Eigen::Vector3d offset_m;
  };
  /// g at x.
  Eigen::Vector3d slip(const Tie& tie, const Eigen::Matrix3Xd& x) const {
    const Eigen::Vector3d s = m_points[static_cast<std::size_t>(tie.point)].load(x);
    return s - m_up.dot(s) * m_up + tie.offset_m;
  }

  std::vector<CarriedSurfacePoint> m_points;
  Eigen::Vector3d m_up;
  double m_height_m;
  double m_coefficient;
  std::vector<Anchor> m_anchors;  ///< per point
  std::vector<Tie> m_ties;        ///< this step's
  // The stiffness slots (ForceField.h): rank-one terms (two a sticking tie, one a sliding one)
  // and their diagonal blocks. Mutable: scratch of the const passes.
  mutable std::array<std::vector<RankOneTerm>, 2> m_terms;
  mutable std::array<RankOneTermDiagonals, 2> m_diagonals;
  mutable int m_current = 0;
  PartBounds m_bounds{};
};

}  // namespace tissuesim
