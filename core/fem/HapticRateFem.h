// SPDX-License-Identifier: Apache-2.0
#pragma once
// The FEM at its own rate, the probe's contact at the haptic rate (multirate haptics: Cavusoglu
// and Tendick 2000; the contact against a condensed compliance as in Saupin, Duriez and Cotin
// 2008). Two parts, each with its own clock:
//
//   update (slow, the FEM's rate): the body taken where the contact in use has it now, Newton
//     iterations under the contact's forces there, and the body linearised where they end:
//     K = d2E/dx2 factorised (CHOLMOD), the body's own out-of-balance force dE/dx, and
//       x(f) = x_rest + B f,   x_rest = x - K^-1 dE/dx,   B = K^-1 E_c   (3#V by 3m)
//     for forces f on the m nodes that carry the surface points near the probe (E_c: their unit
//     loads; 3m + 1 solves): the next CondensedCapsuleContact, C = B's rows of those nodes,
//     xFree their x_rest, the points' penalty on them, each point with its index in the surface
//     (pointIds; the points the grasp holds among them wherever they are).
//   step (fast, 1 kHz): that contact solved for the probe's pose
//   (forces/CondensedCapsuleContact.h).
//
// The iteration between the two is staggered: the body's nonlinearity (the tissue's stiffening,
// large rotations, the contact's geometry over the body) enters at the update's rate, and between
// updates the body answers the probe linearly, but for one scalar: the tissue stiffens with the
// load, and the tangent taken where an update started ages while the probe presses on, so each
// update hands its contact the stiffening it has measured, k(F) = k_lin + beta (F - F_lin) along
// the load (below, kStiffeningLoad_N; CondensedCapsuleContact::setStiffening). It holds while
// the probe travels a fraction of a millimetre between updates from rest, about a millimetre once
// pressed in (docs/performance-details.md has the reach measured). K is the definite tangent
// (FemTangent::Definite), since the update factorises it with no line search to catch an indefinite
// one; the equilibrium it iterates to is the exact energy's.
//
// Shapes: x 3 by #V (m); the surface points' nodes are the model's mesh's.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "fem/BlasThreads.h"
#include "fem/FemModel.h"
#include "fem/FemStaticSolver.h"
#include "forces/CapsulePenalty.h"
#include "forces/CondensedCapsuleContact.h"
#include "forces/NodalLoads.h"
#include "forces/SummedEnergies.h"

namespace tissuesim {

struct HapticRateUpdate {
  bool isStepped = false;       ///< false: no admissible step or no definite Hessian (x kept)
  bool hasNext = true;          ///< false: no new contact made (no definite Hessian within reach,
                                ///< or isOutOfBalance)
  bool isOutOfBalance = false;  ///< Newton left more than the linearisation allows (below)
  /// Surface points of the last contact the probe has gone through (kGoneThrough_m): the probe
  /// went through the surface it was pressing, faster than the updates followed. The new contact
  /// is made all the same, without the points passed through.
  bool isPassedThrough = false;
  int points = 0;           ///< the new contact's surface points
  int candidates = 0;       ///< and the nodes that carry them
  double residual_N = 0.0;  ///< max |dE/dx| on a free DOF after the Newton iterations
};

class HapticRateFem {
 public:
  /// An update whose Newton iterations leave more than this on a free DOF (N), plus this share of
  /// the largest load on a node (in this update or the one before), takes as many iterations
  /// again, once; still out of balance, it makes no new contact: the probe has moved further
  /// than one update can follow (the updates of a poke the scheme follows leave far less:
  /// docs/performance-details.md, "The FEM at its own rate in a scene").
  static constexpr double kLinearisableResidual_N = 0.05;
  static constexpr double kLinearisableLoadShare = 0.05;
  /// The rounds of iterations an update takes, where out of balance: under the probe's load
  /// (points that unload from their peaks meet the softened curve's steep fall there, which the
  /// tangent at the round's start does not foresee), and on a body with no load from the probe
  /// now or at the last update (it springs back behind no probe).
  static constexpr int kRoundsUnderLoad = 3;
  static constexpr int kRoundsWithNoLoad = 4;
  /// The largest |dE/dx| on a free DOF (N) at which Newton stops: settle()'s, and an update's on
  /// a body with no load (which, unlike one under load, goes on to it: above).
  static constexpr double kSolverTolerance_N = 1e-6;
  /// A surface point deeper inside the probe than this at an update (m) is no contact: the
  /// penalty holds a pressed point within micrometres of the probe, so the probe has passed it.
  static constexpr double kPassedThrough_m = 1e-4;
  /// A point of the last contact deeper inside the probe than this at an update (m): the probe
  /// has gone through the surface it pressed (HapticRateUpdate::isPassedThrough). Points a
  /// punctured surface lets slip round the tip end up 1 to 1.5 mm inside it; an update's Newton
  /// iteration behind a withdrawing probe leaves a pressed point up to about 0.1 mm inside.
  static constexpr double kGoneThrough_m = 5e-4;
  /// The body's stiffening between updates (CondensedCapsuleContact::setStiffening): each update
  /// under a load of at least kStiffeningLoad_N (N, the size of the contact's forces' sum) hands
  /// its contact k(F) = k_lin + beta (F - F_lin), beta found from two such updates whose loads
  /// differ by a factor of at least exp(kStiffeningLoadChange): the change of the stiffness
  /// k = F^2 / (f . K^-1 f) of the first one's load pattern f over the change of the load (the
  /// slope between the two loads), carried to the later load as a slope that falls as 1 / F
  /// (k ~ ln F over the interval), held to [0, kMaxStiffeningRate_per_m]. A press finds its own: an
  /// update under less load (the probe clear, or a press's first touch) hands none, and forgets
  /// beta (docs/performance-details.md, "The body's stiffening between updates").
  static constexpr double kStiffeningLoad_N = 0.01;
  static constexpr double kStiffeningLoadChange = 0.05;
  static constexpr double kMaxStiffeningRate_per_m = 1e4;

  /// The candidates' reach grows with the probe's pace: each update's contact takes the points
  /// within candidateMargin_m plus this many times the probe's travel (its tip's) since the last
  /// update, since that contact is in use from one latency after the update starts to two, while
  /// the probe goes on as far again; the margin at most kLargestCandidateMargin_m (m, unless
  /// candidateMargin_m is wider): twice the travel an update at the window's tool limit near the
  /// organ, where a wider contact (a probe put elsewhere between two updates, or moved faster
  /// through the API) costs each haptic step more than it buys (its dense Newton grows as the
  /// cube of the candidates; docs/performance-details.md, "The candidates' margin").
  static constexpr double kCandidateTravelShare = 2.0;
  static constexpr double kLargestCandidateMargin_m = 0.001;

  /// `model` (its tangent set definite here, no extra energy: the contact is the haptic
  /// loop's) must outlive this object. isFixed: 3#V flags. surface: the points the probe may
  /// touch (CapsulePenalty's, on the model's nodes). A point within the probe's radius plus
  /// candidateMargin_m (plus the travel's share, above) of its axis segment at an update is in
  /// the next contact, unless it is more than kPassedThrough_m inside the probe (passed
  /// through, not pressed).
  /// newtonIterations: an update's, >= 0 (0: the body linearised where the contact has it).
  /// support: what holds the body besides its fixed DOFs and loads it besides the probe (its
  /// weight, a tray: an energy that must outlive this object; null: none), in every update.
  /// The process's BLAS runs on one thread while this object lives (fem/BlasThreads.h).
  /// @throws std::invalid_argument on a size or setting out of range.
  HapticRateFem(FemModel& model, std::vector<char> isFixed,
                std::vector<CapsulePenalty::Point> surface, double candidateMargin_m,
                int newtonIterations, const FemExtraEnergy* support = nullptr);

  /// Newton iterations that bring the body from rest to its balance under the support alone.
  static constexpr int kSettlingIterations = 100;

  /// The body brought to balance under the support with no contact (Newton from rest, to the
  /// solver's tolerance within kSettlingIterations) and linearised there into `next`; restart()
  /// returns to it. Without a support the body at rest is its balance. hasNext false where
  /// Newton does not get there (the body is then left at rest, and restart() returns there).
  HapticRateUpdate settle(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m,
                          double radius_m, CondensedCapsuleContact& next);

  /// One update against the probe's pose as given, from the body where inUse (the contact the
  /// haptic loop solves now) has it: fills next (allocates); a copy of inUse where no definite
  /// Hessian is within reach.
  HapticRateUpdate update(const CondensedCapsuleContact& inUse, const Eigen::Vector3d& tip_m,
                          const Eigen::Vector3d& top_m, double radius_m,
                          CondensedCapsuleContact& next);

  /// The same from the body where a contact had it: body_m (3 by #V; null: where the last update
  /// linearised it), the contact's candidates and the forces on them (3 by m, N). Where no
  /// definite Hessian is within reach, `next` is left as it was (hasNext false). For a caller
  /// that updates from a copy of what its contact held (the haptic loop solving on meanwhile).
  /// @throws std::invalid_argument on a size that is not the mesh's or the candidates'.
  HapticRateUpdate update(const Eigen::Matrix3Xd* body_m, const std::vector<int>& candidates,
                          const Eigen::Matrix3Xd& candidateForces_N, const Eigen::Vector3d& tip_m,
                          const Eigen::Vector3d& top_m, double radius_m,
                          CondensedCapsuleContact& next);

  /// The body linearised where body_m (3 by #V) has it, with no load and no Newton iteration:
  /// x_rest = x - K^-1 dE/dx there, whatever dE/dx is (the body kept where another material
  /// had it, the forces it takes to hold it there found by the contact). `next` filled as by
  /// update(); left as it was where body_m is not admissible or has no definite Hessian.
  /// @throws std::invalid_argument on a size that is not the mesh's.
  HapticRateUpdate linearizeAt(const Eigen::Matrix3Xd& body_m, const Eigen::Vector3d& tip_m,
                               const Eigen::Vector3d& top_m, double radius_m,
                               CondensedCapsuleContact& next);

  /// The next update starts from the body settled (after a reset of the scene): settle()'s
  /// balance, or the body at rest before any, with the model's softening history (where it has
  /// softening) back to that balance's strains. settle() takes that history where it leaves the
  /// body, each update and linearizeAt() where they start (FemModel::softenAt).
  void restart();

  /// Whether each update hands its contact the body's stiffening (kStiffeningLoad_N; on by
  /// default): off, the body answers linearly between updates, as measured against.
  void setStiffeningBetweenUpdates(bool isOn) { m_isStiffening = isOn; }

  /// Surface points (indices into the surface given at construction) the next updates keep in
  /// their contact whatever their distance from the probe: the points the grasp holds.
  void setHeldPoints(std::vector<int> points);
  const std::vector<CapsulePenalty::Point>& surface() const { return m_surface; }

  /// The body where the last update linearised it (3 by #V).
  const Eigen::Matrix3Xd& positions() const { return m_x; }

 private:
  /// The next contact from the last factorisation at m_x: x_rest, the candidates near the probe
  /// and their compliance (the points and candidates counted into report).
  /// @returns how many of the last contact's surface points the probe has gone through.
  int linearize(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m, double radius_m,
                CondensedCapsuleContact& next, HapticRateUpdate& report);

  /// The stiffening between updates where the next contact's loads sum to `load_N` (N): the
  /// body's response to them, K^-1 f, into loadResponse (3 by #V), beta found afresh where the
  /// last pattern allows; returns the next contact's rate b = beta f.K^-1 f / F^2 (1/N; 0: the
  /// next contact is linear).
  double stiffening(double load_N, Eigen::Matrix3Xd& loadResponse);

  /// OpenBLAS's threaded dense kernels (CHOLMOD's supernodes) round differently on one thread
  /// and on several, and an update near the refusal threshold flips with them: one thread, while
  /// the scheme lives, keeps its results the same whatever the environment sets; its updates
  /// share the cores with the haptic step and the window's drawing besides.
  OneBlasThread m_oneBlasThread;
  FemModel& m_model;
  NodalLoads m_loads;            ///< the contact's forces
  SummedEnergies m_extraEnergy;  ///< m_loads and the support
  std::vector<char> m_isFixed;
  std::vector<CapsulePenalty::Point> m_surface;
  double m_candidateMargin_m;
  /// The probe's tip at the last contact made (none: no travel counted at the next).
  std::optional<Eigen::Vector3d> m_lastTip_m;
  std::optional<Eigen::Vector3d> m_settledTip_m;  ///< settle()'s, which restart() returns to
  int m_newtonIterations;                         ///< an update's
  FemStaticSolver m_solver;
  Eigen::Matrix3Xd m_x, m_body, m_candidate;
  Eigen::Matrix3Xd m_settled;        ///< where restart() puts the body
  double m_lastLargestLoad_N = 0.0;  ///< the last update's largest load on a node
  std::vector<char> m_isInContact;   ///< per surface point: in the last contact made
  std::vector<int> m_heldPoints;     ///< setHeldPoints', sorted
  /// The stiffening: on (setStiffeningBetweenUpdates), the last load pattern beta was or will be
  /// found from (3#V; empty: none), its sum's size (N), the body's compliance to it there
  /// (m/N), beta so far (1/m), and the solves' workspace.
  bool m_isStiffening = true;
  Eigen::VectorXd m_lastLoadPattern;
  double m_lastLoad_N = 0.0;
  double m_lastLoadCompliance_m_N = 0.0;
  double m_stiffeningRate_per_m = 0.0;
  Eigen::MatrixXd m_loadPatterns, m_loadResponses;
  Eigen::Matrix3Xd m_loadResponse;
};

}  // namespace tissuesim
