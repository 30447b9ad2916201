// SPDX-License-Identifier: Apache-2.0
#pragma once
// A rigid capsule's contact at the haptic rate against a body's compliance condensed onto the
// surface nodes near it: the constraint-based haptics of Saupin, Duriez and Cotin (2008), SOFA's
// "constraint correction", with CapsulePenalty's penalty on points of the surface as the law.
//
//   x_c(u) = xFree + u,   f = C^-1 u          (the m candidates' positions and forces, 3m)
//   E(u) = 1/2 u^T C^-1 u + sum_p k_p e(g_p),   g_p = |s_p - c_p| - R,   s_p = sum_a w_pa x_c,a
//
// xFree: where the candidates settle with no contact, the body linearised about its last solved
// state; C: the body's compliance there, [K^-1] on the candidates' rows and columns (m/N). Point
// p lies between three candidates (weights w_pa summing to 1), c_p is the closest point of the
// capsule's axis segment, k_p its penalty (N/m), e the smoothed penalty (SmoothedPenalty.h). The
// unknowns are the candidates' displacements u, not the points' forces, since the points are
// many (hundreds near a probe) and the candidates few: E is minimised by Newton with a
// backtracking search, its Hessian C^-1 + sum_p k_p e''(g_p) w w^T (n_p n_p^T) (Gauss-Newton's,
// always positive definite) for the first iterations, then with the normals' turning
// k_p e'(g_p) w w^T d2g_p/ds2 added, or a half or a quarter of it, where that is still
// positive definite (Gauss-Newton alone converges only linearly along the surface), to a
// hundredth of a millinewton on a candidate. The force on the capsule is minus the candidates'
// forces' sum.
//
// Optionally some points are held to targets the caller moves with the probe (the grasp: the
// surface the closed jaws caught), each by a spring, which pulls as well as pushes:
//
//   E_h = 1/2 k_h |s_h - t_h|^2   (k_h N/m, s_h a point between three candidates as above)
//
// added to E, its Hessian k_h w w^T I. Optionally the whole body follows the candidates' forces
// linearly: x = xRest + B f (xRest 3 by #V, B 3#V by 3m, the body's compliance on the
// candidates' columns).
//
// Optionally the body stiffens with the load between updates (its tangent, taken where it was
// linearised under loads f_lin of total F_lin, ages while the probe presses on): with the
// stiffness along the load growing as k(F) = k_lin (1 + b (F - F_lin)), the body answers the
// increment from the linearised state with that law's secant,
//
//   x = x_lin + S B (f - f_lin),   x_lin = xRest + B f_lin,   S = ln(1 + z) / z,
//   z = b (F - F_lin)   (held to [-0.9, 2.51]: 0.5 <= S <= 2.56),
//
// i.e. C -> S C, xFree -> xFree + (1 - S) C f_lin (the candidates' rows), xRest -> xRest +
// (1 - S) B f_lin; S is taken from the last solve's total force F = |sum f| (a step behind, so
// that E stays quadratic in u within a solve). Unloaded, the law's secant takes the body back past
// xRest, as a stiffening body's is from a tangent taken under load.

#include <vector>

#include <Eigen/Core>

namespace tissuesim {

class CondensedCapsuleContact {
 public:
  /// The candidates (node ids, whatever numbering the caller keeps): sizes C, xFree and the
  /// body's response, all zero, and drops the points (allocates; the solve does not).
  void setCandidates(const std::vector<int>& nodes);
  const std::vector<int>& candidates() const { return m_nodes; }

  /// C (3m by 3m, symmetric positive definite, node-major) and xFree (3 by m): the caller fills
  /// both after setCandidates, then calls setPoints.
  Eigen::MatrixXd& compliance() { return m_compliance; }
  Eigen::Matrix3Xd& freePositions() { return m_free; }

  /// The points: each three candidates' local indices (columns of localNodes), their weights
  /// and the point's penalty k_p (N/m, > 0). Inverts C (allocates). @throws
  /// std::invalid_argument on a size, index or stiffness out of range, or a C that is not
  /// positive definite.
  void setPoints(const Eigen::Matrix3Xi& localNodes, const Eigen::Matrix3Xd& weights,
                 const Eigen::VectorXd& stiffness_N_m);

  /// The caller's ids of the points (one a point, in setPoints' order; empty: none kept).
  std::vector<int>& pointIds() { return m_pointIds; }
  const std::vector<int>& pointIds() const { return m_pointIds; }

  /// Points held to targets (the grasp): each three candidates' local indices and weights, as
  /// setPoints', held by a spring of heldStiffness_N_m to its column of heldTargets(), which the
  /// caller sets before each solve (allocates; none: no point held). The targets start where
  /// the points are. @throws std::invalid_argument on a size or index out of range.
  void setHeldPoints(const Eigen::Matrix3Xi& localNodes, const Eigen::Matrix3Xd& weights);
  Eigen::Index heldCount() const { return m_heldNodes.cols(); }
  /// A point's position at the last solve (m).
  Eigen::Vector3d pointPosition(Eigen::Index p) const;
  /// A held point's position at the last solve (m).
  Eigen::Vector3d heldPosition(Eigen::Index h) const;
  Eigen::Matrix3Xd& heldTargets() { return m_heldTargets; }
  /// Where a held point settles with no force on the body (m): at xFree.
  Eigen::Vector3d heldFreePosition(Eigen::Index h) const;
  double heldStiffness_N_m = 0.0;

  /// Optionally the whole body: xRest (3 by #V) and B (3#V by 3m), filled after setCandidates;
  /// B left empty, no body.
  Eigen::Matrix3Xd& bodyAtRest() { return m_bodyRest; }
  Eigen::MatrixXd& bodyResponse() { return m_bodyResponse; }
  bool hasBody() const { return m_bodyResponse.size() > 0; }
  /// Optionally the body's stiffening between updates (above): the whole body's displacement
  /// under the loads it was linearised at (3 by #V, B_full f_lin; the candidates' columns are
  /// taken from it), the size of their sum F_lin (N) and the rate b (1/N). Called after
  /// setPoints and bodyAtRest (allocates); setCandidates drops it. @throws std::invalid_argument
  /// on a size, load or rate out of range.
  void setStiffening(const Eigen::Matrix3Xd& loadResponse_m, double linearisedLoad_N,
                     double rate_per_N);
  /// The compliance's scale S at the last solve: 1 without stiffening.
  double complianceScale() const { return m_scale; }
  /// S = ln(1 + z) / z, z = rate (F - F_lin) held to [-0.9, 2.51] (1 at z = 0).
  static double secantScale(double load_N, double linearisedLoad_N, double rate_per_N);

  /// The whole body at the last solve's forces (3 by #V; allocates when x is not that size).
  void bodyPositions(Eigen::Matrix3Xd& x) const;
  /// Its first x.cols() nodes alone (x sized by the caller, at most #V columns; no allocation),
  /// under the candidates' forces given (3 by m, N; nodeForces() for the last solve's).
  void firstBodyPositions(const Eigen::Matrix3Xd& forces_N, Eigen::Matrix3Xd& x) const;

  /// The next solve starts from the displacement other's forces give here, on the candidates
  /// both hold (no allocation).
  void startFrom(const CondensedCapsuleContact& other);

  /// The contact with the capsule from tip_m (its hemisphere's centre) to top_m, radius_m (no
  /// allocation). @returns the force the candidates exert on the capsule (N).
  Eigen::Vector3d solve(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m,
                        double radius_m);

  /// At the last solve: the candidates' positions (3 by m), the forces on them (3 by m, N),
  /// whether Newton met its tolerance, its iterations, and the largest force it left out of
  /// balance on a candidate (N; below the tolerance where it converged).
  const Eigen::Matrix3Xd& positions() const { return m_positions; }
  const Eigen::Matrix3Xd& nodeForces() const { return m_forces; }
  bool converged() const { return m_converged; }
  int iterations() const { return m_iterations; }
  double residual_N() const { return m_residual_N; }

 private:
  /// The point between three candidates (nodes, weights: column p) at displacement u (null: at
  /// xFree).
  Eigen::Vector3d between(const Eigen::Matrix3Xi& nodes, const Eigen::Matrix3Xd& weights,
                          Eigen::Index p, const Eigen::VectorXd* u) const;
  /// The points' penalty energy and the held points' springs' at u (J), their gradient and
  /// Gauss-Newton Hessian added where non-null (both or neither), and the normals' turning, the
  /// rest of the exact Hessian, where `turning` is (with them); touching: whether any point is
  /// within the penalty's reach or held.
  double pointsEnergy(const Eigen::VectorXd& u, const Eigen::Vector3d& tip_m,
                      const Eigen::Vector3d& top_m, double radius_m, Eigen::VectorXd* gradient,
                      Eigen::MatrixXd* hessian, Eigen::MatrixXd* turning,
                      bool* touching = nullptr) const;

  std::vector<int> m_nodes;
  Eigen::MatrixXd m_compliance, m_inverse;  ///< C and C^-1
  Eigen::Matrix3Xd m_free, m_positions, m_forces;
  Eigen::Matrix3Xi m_pointNodes;
  Eigen::Matrix3Xd m_pointWeights;
  Eigen::VectorXd m_pointStiffness_N_m;
  std::vector<int> m_pointIds;
  Eigen::Matrix3Xi m_heldNodes;
  Eigen::Matrix3Xd m_heldWeights, m_heldTargets;
  Eigen::VectorXd m_u, m_trialU, m_gradient, m_step, m_work;
  Eigen::MatrixXd m_hessian, m_turning, m_exact;  ///< Gauss-Newton's, the rest, their sum
  Eigen::Matrix3Xd m_bodyRest;
  Eigen::MatrixXd m_bodyResponse;
  /// Applies the scale S to C, C^-1, xFree and u (the candidates' positions kept).
  void applyScale(double scale);
  /// The stiffening (setStiffening): C, C^-1 and xFree at S = 1, B_full f_lin and its
  /// candidates' columns, F_lin, b, and the scale in use.
  Eigen::MatrixXd m_complianceLinear, m_inverseLinear;
  Eigen::Matrix3Xd m_freeLinear, m_loadResponse, m_candidatesLoadResponse;
  double m_linearisedLoad_N = 0.0;
  double m_rate_per_N = 0.0;
  double m_scale = 1.0;
  bool m_converged = true;
  int m_iterations = 0;
  double m_residual_N = 0.0;
};

}  // namespace tissuesim
