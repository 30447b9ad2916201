// SPDX-License-Identifier: Apache-2.0
#pragma once
// Instrument contacts as penalty terms that the integrators evaluate at every trial state, so
// that an implicit step carries the contact's stiffness in its Newton matrix and the penalty
// can be stiff (10^4 N/m and more) where an explicit penalty is capped by stability.
//
// Each contact is frozen for one step by the collision code: a point on the tissue
//   s(x) = sum_k w_k x_k                      (m; k over the up to four nodes that carry it)
// that must stay below the plane n . y = offset (n the surface's outward normal, unit):
//   delta(x) = n . s(x) - offset             penetration (m), active when > 0
//   E = k delta^2 / 2,   f_k = -k delta w_k n (N),   K_ij = k w_i w_j n n^T (N/m)
// The carrying nodes are a tet's four for a point on the drawn surface (w: the point's
// barycentric coordinates in the tet that holds it at rest, the interpolation that moves the
// drawn surface, so f_k is its transpose, as SOFA's mapped collision models apply forces), or a
// boundary triangle's three (w_3 = 0) for a point on the tet mesh's own surface. An inactive
// contact (delta <= 0 at the trial state) adds nothing; a contact found a little before touching
// activates inside the step if the tissue reaches it. The reaction on the instrument is minus
// the sum of f_k, and its torque is taken about the tip. Nodes of one contact must be joined by
// springs (a tet's nodes and a surface triangle's corners are, being tet edges).

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

#include "forces/ForceField.h"
#include "numerics/NodeBlockMatrix.h"
#include "numerics/RankOneTerm.h"
#include "numerics/RankOneTermDiagonals.h"

namespace tissuesim {

/// What the instrument feels (a haptic device renders force and torque) and how deep it is.
struct ContactResult {
  Eigen::Vector3d toolForce_N = Eigen::Vector3d::Zero();    ///< on the instrument
  Eigen::Vector3d toolTorque_Nm = Eigen::Vector3d::Zero();  ///< on the instrument, about the tip
  double maxPenetration_m = 0.0;
  int contactNodes = 0;  ///< contact points (triangles or nodes) pushing
};

struct PenaltyContact {
  /// The carrying nodes; an unused slot (weight 0) repeats nodes[0].
  std::array<int, kMaxTermNodes> nodes{};
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();  ///< barycentric, summing to 1
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit, out of the tissue
  double offset_m = 0.0;
  double stiffness_N_m = 0.0;
  double damping_N_s_m = 0.0;  ///< c (N s/m): explicit integrator only (applyImpulses)
  /// A support's (the tray under the organ), not the instrument's: left out of what the
  /// instrument feels (reaction) and out of the terms CG's preconditioner inverts exactly.
  bool isSupport = false;
  /// A support's point this contact stands for (its index in the support's list), the same from
  /// step to step, so that an integrator can keep a support's unchanging terms factorised
  /// (QuasiNewtonSolver); -1 for any other contact.
  int supportPoint = -1;
  /// One of a grasp's springs (Grasp.h), which pull as well as push: its force counts in what
  /// the instrument feels (reaction), its delta not as penetration.
  bool isTether = false;

  Eigen::Vector3d point(const Eigen::Matrix3Xd& x) const {
    return weights[0] * x.col(nodes[0]) + weights[1] * x.col(nodes[1]) +
           weights[2] * x.col(nodes[2]) + weights[3] * x.col(nodes[3]);
  }
  double penetration(const Eigen::Matrix3Xd& x) const { return normal.dot(point(x)) - offset_m; }
};

/// The contacts of one step as a force field: their stiffness is kept as rank-one terms (the
/// instrument's first), which the matrix-free operator applies and CG's preconditioner inverts.
class PenaltyContactSet final : public ForceField {
 public:
  static constexpr std::size_t kReservedContacts = 256;

  /// Room for a step's contacts without allocating.
  PenaltyContactSet() { reserve(kReservedContacts); }
  /// Room for `count` contacts (a scene with a tray: its points and the instrument's).
  void reserve(std::size_t count);

  void clear() { m_contacts.clear(); }
  void add(const PenaltyContact& contact) { m_contacts.push_back(contact); }
  bool empty() const { return m_contacts.empty(); }
  const std::vector<PenaltyContact>& contacts() const { return m_contacts; }

  /// forces (3 by #V, N) += the active contacts' forces at x.
  void addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& forces) const;
  /// The explicit integrator's contacts, as impulses on velocities v (3 by #V, m/s) after a
  /// substep's velocity update of h (s), before positions move. Each contact is a spring-damper
  /// on its normal velocity u = n . s(v), with effective mass m_e = 1 / sum_k w_k^2 / m_k (nodes
  /// with a fixed DOF do not move), stepped by backward Euler on its own:
  ///   lambda = (h k delta + (h^2 k + h c) u) / (1 + (h^2 k + h c) / m_e),  lambda >= 0 (push only)
  ///   v_k -= (w_k / m_k) lambda n          (lambda: the impulse on the tissue, N s)
  /// one contact after another (Gauss-Seidel). Exact for each contact alone at any h, so the
  /// contacts bound nothing: an explicit penalty of 10^4 N/m on a light surface node would need
  /// sub-microsecond steps (a 7.5 mg node of the liver asked for 65 substeps of a 1 ms step).
  /// The implicit integrators do not use it: they evaluate the contacts as forces.
  /// Returns the impulse the instrument's contacts (not a support's) gave the tool, sum of
  /// lambda n (N s): what the tool felt over the substep, which k delta at the substep's end
  /// understates (the impulses have already pushed the surface back).
  Eigen::Vector3d applyImpulses(const Eigen::Matrix3Xd& x, const Eigen::VectorXd& mass_kg,
                                const std::vector<char>& isFixed, double h,
                                Eigen::Matrix3Xd& v) const;
  /// stiffness += the active contacts' blocks k w_i w_j n n^T at x.
  void addStiffness(const Eigen::Matrix3Xd& x, NodeBlockMatrix& stiffness) const;
  /// The same stiffness as rank-one terms k u u^T, u = (w_0 n, ..., w_3 n), for the matrix-free
  /// operator and CG's preconditioner (BlockConjugateGradient): terms is overwritten with the
  /// contacts active at x, u zeroed on the DOFs flagged in isFixed (3#V), as applyFixedDofs
  /// zeroes the matrix's. The instrument's come first; returns their count (the terms worth
  /// inverting exactly: a few, stiff, on light surface nodes; a support's hundreds stay in the
  /// block diagonal).
  std::size_t rankOneTerms(const Eigen::Matrix3Xd& x, const std::vector<char>& isFixed,
                           std::vector<RankOneTerm>& terms) const;
  /// The reaction on the instrument at x (force, torque about tip_m, deepest penetration,
  /// active contacts), from the instrument's contacts alone.
  ContactResult reaction(const Eigen::Matrix3Xd& x, const Eigen::Vector3d& tip_m) const;

  // ForceField. K: the exact sum of k w_i w_j n n^T over the active contacts (PSD).
  const char* name() const override { return "contacts"; }
  /// sum over the active contacts of k delta^2 / 2 (J).
  double energy(const Eigen::Matrix3Xd& x) const override;
  /// The terms at x, u zeroed on pass.fixedDofs, into the slot; the node bound adds k w_k.
  void addForces(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& f, const ForcePass& pass,
                 ForceReport& report) const override;
  void acceptTrialStiffness() const override { m_current ^= 1; }
  void prepareProducts(const PartBounds& bounds) override;
  void addStiffnessProduct(int part, const double* x, double* y) const override;
  void addDiagonalBlock(Eigen::Index j, Eigen::Matrix3d& block) const override;
  void addStiffness(NodeBlockMatrix& matrix) const override;
  /// The current slot's instrument terms: the few stiff ones on light surface nodes that CG's
  /// preconditioner inverts exactly (a support's hundreds stay in the block diagonal).
  std::span<const RankOneTerm> instrumentTerms() const {
    const auto slot = static_cast<std::size_t>(m_current);
    return {m_terms[slot].data(), m_instrumentTermCount[slot]};
  }

 private:
  /// rankOneTerms() with isFixed optional (null: none fixed).
  std::size_t collectTerms(const Eigen::Matrix3Xd& x, const std::vector<char>* isFixed,
                           std::vector<RankOneTerm>& terms) const;

  std::vector<PenaltyContact> m_contacts;
  // The stiffness slots (ForceField.h): terms, how many are the instrument's, and their diagonal
  // blocks (sized by prepareProducts()). Mutable: scratch of the const passes.
  mutable std::array<std::vector<RankOneTerm>, 2> m_terms;
  mutable std::array<std::size_t, 2> m_instrumentTermCount{};
  mutable std::array<RankOneTermDiagonals, 2> m_diagonals;
  mutable int m_current = 0;
  PartBounds m_bounds{};
  bool m_hasDiagonals = false;
};

}  // namespace tissuesim
