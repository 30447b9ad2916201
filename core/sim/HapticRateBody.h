// SPDX-License-Identifier: Apache-2.0
#pragma once
// A scene's organ as the continuum reference's element at its own rate, the probe's contact at
// the haptic rate (effects.model "fem-haptic-rate"; fem/HapticRateFem.h has the scheme): the
// scene's tet mesh made quadratic (one dilatation per tet, FemModel.h), its boundary bent onto the
// drawn surface where the scene has one (fem/CurvedBoundary.h), its surface sampled for the
// probe's penalty (fem/SampledSurface.h), the fixed nodes held, weightless unless the
// settings give gravity (below).
//
// Two clocks on two threads. The haptic step (the caller's, 1 kHz) solves the probe's contact
// against the body's compliance condensed onto the surface nodes near it, and moves the whole
// body linearly with the contact's forces: x = x_rest + B f. An update (a worker thread of its
// own) takes the contact's forces and the body where the step started it, runs Newton under them
// and linearises the body there; the haptic step takes the new contact from then on:
//
//   latencySteps > 0: exactly that many steps after the update started (the step waits for it
//     if it is not done): deterministic, as a recorded session or a test needs;
//   latencySteps = 0: from the first step after it is done (the window's real time).
//
// The next update starts at the step that takes the last one in, from the contact's last settled
// state: a step whose contact does not settle is rolled back to it (the body drawn and the force
// reported are the last settled ones). Where it would repeat the last one (the body balanced to the
// solver's tolerance there, the probe where it was, the load on the body changed by less than what
// that tolerance leaves), none starts until something changes: a body at rest, free or under a
// probe held still, costs its thread nothing, and the window's other threads have the machine. With
// softening (the settings'), each update takes the material points' history
// (fem/IsochoricSoftening.h) where it starts, and a reset clears it. Under gravity (the consistent
// loads of its weight, fem/QuadraticTetWeight.h) and on a tray (a penalty on the sampled surface,
// as the probe's, forces/PlanePenalty.h), both in every update's Newton iterations, the body starts
// where it balances them with no probe (HapticRateFem::settle), and a reset returns it there.
// Shapes: positions 3 by #V (m), the first #corners of them the scene's mesh's nodes in its order.

#include <condition_variable>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "fem/CurvedBoundary.h"
#include "fem/FemModel.h"
#include "fem/HapticRateFem.h"
#include "fem/QuadraticTetMesh.h"
#include "forces/CondensedCapsuleContact.h"
#include "forces/NodalLoads.h"
#include "forces/PlanePenalty.h"
#include "forces/SummedEnergies.h"
#include "material/StrainEnergy.h"
#include "material/StressSoftening.h"
#include "mesh/TetMesh.h"
#include "mesh/TriangleSurface.h"
#include "sim/Grasp.h"

namespace tissuesim {

/// A tray under the body (forces/PlanePenalty.h): up . y >= height_m, its penalty per unit area.
struct HapticRateTray {
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  double height_m = 0.0;
  double stiffness_Pa_per_m = 1e7;
};

struct HapticRateBodySettings {
  double probeRadius_m = 0.0025;
  double contactSpacing_m = 0.001;       ///< the surface's penalty points, about this far apart
  double pressureStiffness_Pa_m = 1e11;  ///< the probe's penalty per unit area
  double candidateMargin_m = 0.0003;     ///< HapticRateFem's (with the probe's travel's share)
  int newtonIterations = 2;              ///< an update's
  long latencySteps = 0;                 ///< > 0: fixed (deterministic); 0: when done
  Eigen::Vector3d gravity_m_s2 = Eigen::Vector3d::Zero();  ///< zero: weightless
  double density_kg_m3 = 1060.0;                           ///< the body's weight with gravity
  std::optional<HapticRateTray> tray;                      ///< none: no tray
  /// The travel a step at which the opening jaws lead the held surface back (m): the tool's
  /// speed limit a step, which the scheme follows.
  double letGoTravel_m = 1e-5;
  /// Stress softening at the body's material points (fem/IsochoricSoftening.h), its
  /// history taken where each update starts; none: the virgin curve.
  std::optional<StressSoftening> softening;
  /// The surface the mesh was made conformal to (must outlive the constructor; null: none): the
  /// boundary's quadratic faces bent onto it (fem/CurvedBoundary.h), so that the probe meets
  /// the tissue where it is drawn rather than on the coarse mesh's chords inside it.
  const TriangleSurface* drawnSurface = nullptr;
  /// The probe's travel between updates that the scheme follows (m; sim/HapticRateReach.h),
  /// named where an update is refused (refusedUpdateReason); 0: none named.
  double reach_m = 0.0;
};

/// Why an update whose Newton iterations left residual_N (N) out of balance was refused, the
/// probe having travelled travel_m (m) since the update before it started, the scheme following
/// reach_m (m; 0: unknown): past the reach, the probe outran the updates; within it, the body did
/// (pressed deep, where the tissue is stiffer than where the reach was measured, or sliding off
/// the frictionless probe, its balance jumping).
std::string refusedUpdateReason(double residual_N, double travel_m, double reach_m);

/// One haptic step's outcome.
struct HapticRateStep {
  Eigen::Vector3d probeForce_N = Eigen::Vector3d::Zero();  ///< on the probe
  /// The contact settled: its Newton met its tolerance, or stopped at its budget with what
  /// sim/UnconvergedResidual.h lets pass (points slipping round the pressed probe as it is
  /// steered sideways leave it creeping at tens of micronewtons); else rolled back.
  bool isSettled = true;
  int contactIterations = 0;
  double contactResidual_N = 0.0;  ///< the largest force its Newton left on a node
  /// The last update taken in could not linearise the body (no definite Hessian within reach,
  /// Newton left out of balance, or an error: `updateProblem`); the contact in use was kept.
  bool isUpdateRefused = false;
  /// The last update taken in found the probe through the surface it was pressing
  /// (HapticRateUpdate::isPassedThrough): it outran the updates (`updateProblem` says so).
  bool isPassedThrough = false;
  int candidates = 0;  ///< the surface nodes the contact in use can move
};

class HapticRateBody {
 public:
  /// fixedNodes: the mesh's held nodes (with the quadratic nodes between two of them); every
  /// quadratic node in fixedBox_m (when given) is held too, as the FEM reference holds it. The
  /// probe (its hemisphere's centre at tip_m, the shaft's end at top_m) starts there; the body at
  /// rest (settled under its weight on the tray, where settings give them) is linearised before
  /// this returns. `energy` must outlive this object.
  /// @throws std::invalid_argument on a mesh, node or setting out of range, or a body that does
  /// not come to balance under its weight.
  HapticRateBody(const TetMesh& mesh, const std::vector<int>& fixedNodes,
                 const std::optional<Eigen::AlignedBox3d>& fixedBox_m, const StrainEnergy& energy,
                 double bulkModulus_Pa, const HapticRateBodySettings& settings,
                 const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m);
  ~HapticRateBody();
  HapticRateBody(const HapticRateBody&) = delete;
  HapticRateBody& operator=(const HapticRateBody&) = delete;

  /// One haptic step with the probe there; corners_m (3 by #corners, sized by the caller) gets
  /// the mesh's nodes. isGrasping: the jaws closed (below). Allocates only when an update's
  /// contact comes in or the jaws close or open.
  HapticRateStep step(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m,
                      Eigen::Matrix3Xd& corners_m, bool isGrasping = false);
  /// The grasp: as the jaws close, the surface points of the contact in use within
  /// kGraspReachRadii probe radii of the hemisphere's centre are held at their offsets from it,
  /// each by a spring (CondensedCapsuleContact's held points), the offsets turned as the shaft
  /// turns (the shortest rotation, as sim/Grasp.h's); the probe feels their pull. Every update
  /// keeps them in its contact while they are held. Opening the jaws lets go (below).
  static constexpr double kGraspReachRadii = 2.0;
  /// Each held point's spring (N/m), as sim/Grasp.h's on a node.
  static constexpr double kHeldStiffness_N_m = Grasp::kDefaultStiffness_N_m;
  /// As the jaws open, the held points' targets are led back to where the points settle with
  /// no force on the body (the contact's xFree), each step a kLetGoApproachSteps-th of the way
  /// left and at most settings' letGoTravel_m, so that the force they carry fades out; the
  /// points are let go once every target has stayed within kLetGoReached_m of it for
  /// kLetGoBackSteps (or two latencies, whichever is longer: the updates meanwhile linearise the
  /// body nearer its rest, and xFree moves on). Let go at once, a lifted liver springs back
  /// further in one update than the updates follow; led back at a constant speed, the force
  /// collapses as the targets arrive, and an update meets that drop. At most
  /// kLongestLetGoSteps, then let go whatever is left.
  static constexpr long kLetGoApproachSteps = 30;
  static constexpr double kLetGoReached_m = 1e-6;
  static constexpr long kLetGoBackSteps = 150;
  static constexpr long kLongestLetGoSteps = 5000;
  /// The surface points held now (indices into the sampled surface).
  const std::vector<int>& heldPoints() const { return m_heldPoints; }
  /// The mesh's nodes (corners) among the held points' (empty when nothing is held).
  std::vector<int> heldCorners() const;
  /// Back to the body at rest (an update in flight is waited for and dropped).
  void reset();
  /// Takes up the body where `other` (on the same mesh, another material: a new tissue) had it
  /// at its last settled step, linearised there with this body's material and no load (before
  /// this returns), so that a probe pressing the organ goes on pressing it; where this material
  /// cannot take that state up, from rest. The probe is where step() last had it in `other`.
  /// @throws std::invalid_argument where `other` is not on the same mesh.
  void continueFrom(HapticRateBody& other, const Eigen::Vector3d& tip_m,
                    const Eigen::Vector3d& top_m);
  /// Takes up the softening `other` (the same scene's organ on another mesh, at rest; an update
  /// in flight there is waited for) has left: each of this body's material points takes the peak of
  /// the nearest point of the element of `other` that holds it at rest (mesh/TetLocator.h, on the
  /// corners), where that is higher than its own, so that what a poke softened stays soft in a body
  /// made again (Simulation::refineTowardsTool). The peaks are strains: the body at rest does not
  /// move. Nothing without softening.
  void takeUpSoftening(HapticRateBody& other);

  Eigen::Index nodeCount() const { return m_mesh.nodeCount(); }
  /// The body's corners (3 by #corners, m) where it starts and a reset returns it: at rest, or
  /// settled under its weight on the tray.
  const Eigen::Matrix3Xd& startCorners() const { return m_startCorners; }
  /// The force the tray carries with the body where it starts (N; zero without a tray).
  const Eigen::Vector3d& startTraySupport_N() const { return m_startTraySupport_N; }
  Eigen::Index tetCount() const { return m_mesh.tetCount(); }
  /// The quadratic body at rest (its boundary bent onto the drawn surface where one was given).
  const QuadraticTetMesh& mesh() const { return m_mesh; }
  /// The boundary's edges bent onto the drawn surface (all left straight without one).
  const CurvedBoundaryReport& curvedBoundary() const { return m_curvedBoundary; }
  std::size_t surfacePoints() const { return m_surfacePoints; }
  const HapticRateBodySettings& settings() const { return m_settings; }
  /// The last refused update's reason (empty when none was).
  const std::string& updateProblem() const { return m_updateProblem; }
  /// The updates started so far (none while the body rests: above).
  long updatesStarted() const { return m_updatesStarted; }
  /// The updates the steps have taken in so far, and their wall time on the worker, all
  /// together (s): what an update costs on this machine.
  long updatesTaken() const { return m_updatesTaken; }
  double updating_s() const { return m_updating_s; }
  /// How long the last step() waited for an update to finish (s): with latencySteps, a step
  /// run faster than real time waits for each update, which a step at 1 kHz finds done where
  /// the update takes less than its latency.
  double lastWait_s() const { return m_lastWait_s; }
  /// The probe's travel since the last update started below which it is still (m).
  static constexpr double kRestingProbeTravel_m = 1e-9;
  /// Nothing presses or holds the body and it is back where it starts, within
  /// kRestingDisplacement_m at every corner: what a new body made for the same scene takes up
  /// without a jump (Simulation::refineTowardsTool).
  bool isAtRest() const;
  static constexpr double kRestingDisplacement_m = 1e-5;

 private:
  void startUpdate(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m);
  /// An update started now would repeat the last one taken in (above): nothing has moved.
  bool wouldRepeatLastUpdate(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m) const;
  /// The last settled step's state: the whole body where its contact has one (@returns whether
  /// it has: else the body at rest), the contact's candidates and the forces on them.
  bool settledState(Eigen::Matrix3Xd& body_m, std::vector<int>& candidates,
                    Eigen::Matrix3Xd& forces_N) const;
  /// The contact in use and the last settled step: the body at rest's.
  void restartSettled();
  /// The held points that are among `contact`'s points held by it (allocates).
  void attachHeld(CondensedCapsuleContact& contact);
  void grasp(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m);
  /// The shortest rotation from the shaft's direction as the jaws closed to its direction now.
  Eigen::Matrix3d shaftTurn(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m) const;
  void startLettingGo(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m);
  /// One step of the opening jaws: the held targets a step nearer xFree, the points let go
  /// once all are there.
  void leadHeldBack();
  void letGo();
  void waitForUpdate();
  void work();

  HapticRateBodySettings m_settings;
  QuadraticTetMesh m_mesh;
  CurvedBoundaryReport m_curvedBoundary;
  std::unique_ptr<FemModel> m_model;
  NodalLoads m_weight;                   ///< empty when weightless
  std::unique_ptr<PlanePenalty> m_tray;  ///< null without a tray
  SummedEnergies m_support;              ///< the two, HapticRateFem's support
  std::unique_ptr<HapticRateFem> m_fem;
  std::size_t m_surfacePoints = 0;
  CondensedCapsuleContact m_start;  ///< the body at its start linearised
  Eigen::Matrix3Xd m_startCorners;
  Eigen::Vector3d m_startTraySupport_N = Eigen::Vector3d::Zero();
  CondensedCapsuleContact m_contacts[2];
  CondensedCapsuleContact* m_inUse = &m_contacts[0];
  CondensedCapsuleContact* m_next = &m_contacts[1];
  // The last settled step: the forces on its contact's candidates (N) and that contact (null once
  // the worker overwrites it: the job's fields then hold that state), the corners, the force.
  Eigen::Matrix3Xd m_settledForces;
  CondensedCapsuleContact* m_settledOwner = nullptr;
  Eigen::Matrix3Xd m_settledCorners;
  Eigen::Vector3d m_settledProbeForce_N = Eigen::Vector3d::Zero();
  long m_stepsSinceUpdate = 0;
  bool m_isInFlight = false;
  bool m_isRefusing = false;       ///< the last update taken in was refused
  bool m_isPassedThrough = false;  ///< the last update taken in: HapticRateUpdate's
  /// The residual (N) the last update taken in left the body with, where it made its contact
  /// and found the probe on the surface; infinite where not, before any, and after a reset.
  double m_lastResidual_N = std::numeric_limits<double>::infinity();
  long m_updatesStarted = 0;
  long m_updatesTaken = 0;
  double m_updating_s = 0.0;
  double m_lastWait_s = 0.0;
  std::string m_updateProblem;

  // The grasp (the haptic thread's): the held surface points, their offsets from the probe's
  // centre as the jaws closed (3 by #held, m), the shaft's direction then, and for each of the
  // contact in use's held points its index among them.
  bool m_wasGrasping = false;
  long m_letGoSteps = 0;              ///< steps since the jaws began to open (0: not opening)
  long m_backSteps = 0;               ///< steps the targets have stayed where the points settle
  Eigen::Matrix3Xd m_letGoTargets_m;  ///< the held points' targets as they are led back
  std::vector<int> m_heldPoints;
  Eigen::Matrix3Xd m_heldOffsets_m;
  Eigen::Vector3d m_closingDirection = Eigen::Vector3d::UnitZ();
  std::vector<int> m_inUseHeld;

  // The job the worker takes (written by the haptic thread while the worker is idle).
  Eigen::Matrix3Xd m_jobBody;
  bool m_jobHasBody = false;
  bool m_jobGoesOn = false;  ///< from the FEM's own state (the last update was refused)
  std::vector<int> m_jobCandidates;
  std::vector<int> m_jobHeld;
  Eigen::Matrix3Xd m_jobForces;
  Eigen::Vector3d m_jobTip = Eigen::Vector3d::Zero(), m_jobTop = Eigen::Vector3d::Zero();
  /// The probe's travel since the update before the job started (m; 0 for the first since the
  /// body was made or reset: m_jobTip is that update's tip only where m_hasJobTip).
  double m_jobTravel_m = 0.0;
  bool m_hasJobTip = false;
  HapticRateUpdate m_jobReport;
  double m_jobWall_s = 0.0;  ///< the job's wall time on the worker
  std::string m_jobError;

  std::mutex m_mutex;
  std::condition_variable m_wake, m_done;
  bool m_hasJob = false, m_isJobDone = false, m_shouldStop = false;
  std::thread m_worker;
};

}  // namespace tissuesim
