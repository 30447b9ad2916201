// SPDX-License-Identifier: Apache-2.0
#pragma once
// The fast iterative method: quasi-Newton implicit Euler of Liu, Bouaziz and Kavan,
// "Quasi-Newton Methods for Real-Time Simulation of Hyperelastic Materials" (ACM TOG 2017),
// the generalisation of Liu et al. 2013 ("Fast Simulation of Mass-Spring Systems") from
// Hookean springs to any hyperelastic energy.
//
// Why this one: the EESM spring is nonlinear (its stiffness rises twenty-fold towards locking),
// which Liu 2013's local/global solver and projective dynamics cannot represent without
// changing the model, and XPBD converges to the right answer only with many iterations. Liu
// 2017 minimises the same implicit-Euler objective as ImplicitEulerSolver,
//
//   g(x) = 1/2 (x - x_hat)^T W M (x - x_hat) + E(x),   grad g = r(x) = W M (x - x_hat) - f(x),
//
// with L-BFGS whose initial Hessian is H0 = W M + L (x) I3 + K_volume, L the graph Laplacian
// weighted by each spring's stiffness at rest, V_e P'(1) / L0^2, and K_volume the volume term's
// stiffness at rest (kappa is tens of times the springs' modulus: left to L-BFGS, the poke
// diverged). H0 is factorised once (per time step size and constraint set), so an iteration
// costs one force evaluation, two triangular solves and O(m) vector operations, with no matrix
// assembly. The iteration count per step is the speed/accuracy knob
// (IntegratorSettings::maxIterations); as it grows the result converges to implicit Euler's.
//
// Contacts: an instrument contact is far stiffer (10^4 N/m) than anything in H0, and L-BFGS
// with a few pairs cannot learn it: the poke diverged. Each step's contacts are rank-one terms
// k (w (x) n)(w (x) n)^T, so H0 + U U^T is inverted by the Sherman-Morrison-Woodbury formula
//   (H0 + U U^T)^-1 q = z - V (I + U^T V)^-1 U^T z,   z = H0^-1 q,  V = H0^-1 U  (3#V by #C)
// at the cost of one solve per contact per step (a handful) and a #C by #C factorisation.
// A step that has not halved the residual of its predictor is diverging or about to (H0 misses
// the stiffness the springs have gained); it iterates past the budget (up to five times it)
// until it has (the report's iteration count shows it). One that has not even then refreshes
// H0: the next step factorises W M plus the fields' stiffness (PSD-projected) at its start, and
// keeps it until another step needs the same (a few times a poke; Eigen's factorisation
// allocates, so a refreshing step is the one step that does). With H0 at rest a deep poke of
// the liver diverged; with the refresh it follows implicit Euler. A step also takes up to
// IntegratorSettings::extraIterations more while its residual is one that would count as an
// event, as Newton's do.
//
// A support's contacts (the tray under the organ) are hundreds, and one solve each a step left
// a poke on the tray far from real time. They hardly change from step to step, so H0 carries them:
// factorised with the support contacts of the step that factorised it, and the Woodbury terms
// take only the differences since (+u u^T for a support contact H0 lacks, -u u^T for one it has
// that the step does not), with the signs in the capacitance, S + U^T V. When the differences
// pass kMaxSupportChanges, H0 is refactorised with the step's support contacts.

#include <memory>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include "integrators/TimeIntegrator.h"
#include "numerics/NodeBlockMatrix.h"
#include "numerics/RankOneTerm.h"

namespace tissuesim {

class QuasiNewtonSolver final : public TimeIntegrator {
 public:
  explicit QuasiNewtonSolver(IntegratorSettings settings) : m_settings(settings) {}
  StepReport step(MechanicalSystem& system, MechanicalState& state, double dt) override;
  const char* name() const override { return "quasi-newton"; }

  /// Support contacts that H0 may lack, or carry without the step having them, before it is
  /// refactorised with the step's.
  static constexpr int kMaxSupportChanges = 16;
  /// How many times H0 has been factorised (tests: a resting support refactorises nothing).
  int factorisationCount() const { return m_factorisationCount; }

 private:
  /// H0 for this weight and the system's constraints (refactorised from the fields' stiffness
  /// at x when the last step asked for it).
  void prepare(const MechanicalSystem& system, double inertiaWeight, const Eigen::Matrix3Xd& x);
  /// The index among the carried terms of the support contact `c` stands for, or -1.
  int carriedIndex(const PenaltyContact& c) const;
  /// Support contacts of the step that H0 lacks, plus those H0 carries that the step lacks.
  int supportChanges(const MechanicalSystem& system);
  /// Makes the step's support contacts the ones H0 carries.
  void foldSupports(const MechanicalSystem& system);
  /// U, V and the factorised capacitance S + U^T V for the contacts H0 does not carry as the
  /// step has them (S: each column's sign).
  void prepareContacts(const MechanicalSystem& system);
  /// z = (H0 + U S U^T)^-1 q.
  void applyInitialInverse(const Eigen::VectorXd& q, Eigen::VectorXd& z);
  double residual(const MechanicalSystem& system, const Eigen::VectorXd& x, Eigen::VectorXd& r,
                  ForceReport* report);

  IntegratorSettings m_settings;
  const MechanicalSystem* m_preparedFor = nullptr;
  double m_preparedWeight = -1.0;
  int m_preparedRevision = -1;
  std::unique_ptr<NodeBlockMatrix> m_h0;      ///< H0 assembled (its pattern: the system's)
  std::unique_ptr<NodeBlockMatrix> m_h0Base;  ///< the same without the support contacts
  int m_factorisationCount = 0;
  // The support contacts H0 carries: their terms (as of its factorisation) and support points,
  // each support point's index among them (-1: not carried), and whether the step has each.
  std::vector<RankOneTerm> m_foldedTerms;
  std::vector<int> m_foldedPoints;
  std::vector<int> m_foldedSlot;
  std::vector<char> m_isFoldedPresent;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> m_initialHessian;
  bool m_isAnalysed = false;       ///< H0's pattern analysed
  bool m_isRefreshWanted = false;  ///< the next step refactorises H0 at its start
  Eigen::VectorXd m_x, m_xHat, m_r, m_newX, m_newR, m_q, m_z, m_alpha, m_rhoHistory;
  Eigen::MatrixXd m_s, m_y;  ///< 3#V by m history of steps and residual changes
  Eigen::Matrix3Xd m_force;
  Eigen::MatrixXd m_contactU, m_contactV;  ///< 3#V by #C (Woodbury)
  Eigen::VectorXd m_columnSign;            ///< S: +1, or -1 for a carried term taken out
  Eigen::MatrixXd m_capacitanceMatrix;     ///< S + U^T V, #C by #C
  Eigen::PartialPivLU<Eigen::MatrixXd> m_capacitance;  ///< its LU (S makes it indefinite)
  Eigen::VectorXd m_projected, m_contactScratch;       ///< #C: U^T z and the capacitance solve
};

}  // namespace tissuesim
