// SPDX-License-Identifier: Apache-2.0
#pragma once
// One simulated scene advanced at a fixed time step: tissue file -> material -> tables ->
// spring mesh -> (contacts in) integration -> state out. What the scene does not name is not
// built: no volume term unless asked, no contact without an instrument and a ContactProvider.
//
// With gravity, the organ starts settled: at construction (and for a new tissue) it is let sag
// onto its support (the tray, the fixed region) with heavy damping and long steps until it is
// still, and that state is where it starts and what reset() returns to (with the tray's grip
// where it came to rest, when the tray has friction); a trainee never sees the organ drop when a
// scene opens.
//
// Each step: the instrument pose at t + dt from the InstrumentSource, the contacts it makes from
// the ContactProvider, the tray's and the grasp's springs (penalty terms the integrator evaluates
// at its trial states: implicit with the implicit integrators), the tray's friction ties from
// where the last good step left them (forces/PlaneFriction.h), one integrator step; a good step
// then moves the ties by Coulomb's law.
// Each good step is added to the session's assessment (SessionAssessment: force, path, damage);
// reset() starts a new one.
// Instabilities (refused or non-finite steps, Newton not converged, springs past locking, collapsed
// springs, inverted tets) are detected every step and recorded as events when they start; a refused
// or non-finite step leaves the last good state in place, so the simulation stays usable.
// Deterministic: no clocks, no randomness inside; threads only where the result does not depend
// on them (the spring passes' pool; the FEM's updates with effects.model fem-haptic-rate at a
// fixed latency, physics.fem_update_latency_ms; at 0 each update is used when it is done, which
// depends on the machine).

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fem/SmoothedStrainForceField.h"
#include "fem/TetIsochoricForceField.h"
#include "forces/ContactProvider.h"
#include "integrators/TimeIntegrator.h"
#include "material/StiffnessTable.h"
#include "sim/Grasp.h"
#include "sim/InstrumentScript.h"
#include "sim/SceneGeometry.h"
#include "sim/SessionAssessment.h"
#include "sim/ToolClearance.h"
#include "sim/TraySupport.h"
#include "springs/NodalVolumeForceField.h"
#include "springs/SpringForceField.h"

namespace tissuesim {

class HapticRateBody;  // sim/HapticRateBody.h (not here: FemModel.h's names meet Qt's macros)

struct InstabilityEvent {
  long step;
  double time_s;
  /// refused, non-finite, unconverged, locking, collapsed, inverted, unsettled, outrun (an FEM
  /// update at its own rate refused: effects.model fem-haptic-rate)
  std::string kind;
  std::string detail;
};

/// The integrator settings a scene's physics block gives, with the real-time step's extra
/// iterations (a step that would leave a residual counted as an event takes a few more first).
IntegratorSettings realTimeIntegratorSettings(const SceneDescription& scene);

/// An event kind in a few words for a status line ("inverted tets"); the kind itself when unknown.
const char* eventKindWords(const char* kind);

/// How many of `events` are of each kind.
std::map<std::string, int> countEventsByKind(const std::vector<InstabilityEvent>& events);
/// Those counts on one line, kinds in name order ("1 inverted, 2 unconverged"); empty for none.
std::string eventKindSummary(const std::vector<InstabilityEvent>& events);

struct StepOutcome {
  StepReport integrator;
  ContactResult contact;
  double maxStretch = 1.0;
  bool isGood = true;  ///< the state advanced and is finite
};

class Simulation {
 public:
  /// Builds everything the scene names. @throws SceneFileError, TissueFileError.
  explicit Simulation(const SceneDescription& scene);
  ~Simulation();

  /// The collision implementation (nullable: no contact). Must outlive this object.
  void setContactProvider(ContactProvider* provider) { m_contact = provider; }
  /// Where the instrument is (nullable: no instrument). Must outlive this object.
  void setInstrumentSource(const InstrumentSource* source) { m_instrument = source; }

  StepOutcome step();
  void reset();

  // Changes while running (the caller pauses any loop stepping this simulation first). The
  // state (positions, velocities, time) is kept; the Mullins memory starts afresh, since it
  // belongs to the material that was replaced (under gravity: the new tissue's settled start's,
  // which is settled again and is where reset() then returns).
  /// A new tissue: material, stiffness tables, masses and spring laws rebuilt. If building
  /// them throws, the simulation is left as it was.
  void replaceTissue(const TissueParameters& parameters);
  /// Stress softening on or off (the scene's effects.softening).
  void setSoftening(bool isOn);
  bool isSoftening() const { return m_scene.isSoftening; }
  void setGravity(const Eigen::Vector3d& gravity_m_s2);
  Eigen::Vector3d gravity() const;
  const TissueParameters& parameters() const { return *m_parameters; }
  /// The current tissue's material and tables (replaced only by replaceTissue/setSoftening).
  const StrainEnergy& energy() const { return *m_energy; }
  const StiffnessTable& table() const { return *m_table; }

  double time_s() const { return m_time_s; }
  long steps() const { return m_steps; }
  double timeStep_s() const { return m_timeStep_s; }
  /// The factor applied to every spring's volume share (see the constructor).
  double stiffnessScale() const { return m_stiffnessScale; }
  /// The volume term's kappa (Pa); 0 when the scene has none.
  double bulkModulus() const { return m_bulkModulus_Pa; }
  const MechanicalState& state() const { return m_state; }
  /// The state itself, writable: for tests of the recovery from a corrupted state (a step that
  /// finds a value that is not finite puts the last good state back and records an event).
  MechanicalState& stateForFaultInjection() { return m_state; }
  /// Where the simulation starts and reset() returns: the rest state, settled under the scene's
  /// gravity when it has any (velocities zero).
  const MechanicalState& startState() const { return m_startState; }
  /// The tray's support (null when the scene has no tray, and for fem-haptic-rate, whose body
  /// holds its own: HapticRateBody::startTraySupport_N).
  const TraySupport* tray() const { return m_tray.get(); }
  /// The tray's friction (null when the scene has no tray or a frictionless one).
  const PlaneFriction* trayFriction() const { return m_friction.get(); }
  const SpringMesh& springMesh() const { return *m_springMesh; }
  const SpringForceField& springs() const { return *m_springs; }
  const SceneGeometry& geometry() const { return m_geometry; }
  const SceneDescription& scene() const { return m_scene; }
  /// The quadratic body at its own rate (null unless effects.model is fem-haptic-rate).
  const HapticRateBody* hapticRateBody() const { return m_hapticRate.get(); }
  /// The first 100 events since the start or the last reset.
  const std::vector<InstabilityEvent>& events() const { return m_events; }
  /// All of them, kept or not.
  std::size_t eventCount() const { return m_eventCount; }
  /// The kind of the latest event (a string literal, as in InstabilityEvent::kind), or null
  /// when there has been none: what a status line can show without copying the list.
  const char* latestEventKind() const { return m_latestEventKind; }
  /// The instrument pose used by the last step (the scene's start pose before any).
  InstrumentPose instrumentPose() const { return m_pose; }
  /// The session so far (since the start or the last reset).
  const SessionAssessment& assessment() const { return *m_assessment; }
  /// Nodes the grasper holds now (empty without an instrument or with open jaws; for
  /// fem-haptic-rate, the mesh's nodes among the held surface points').
  std::vector<int> heldNodes() const;

  // Refined again where the tool aims (effects.model fem-haptic-rate with
  // tet_mesh.refine_towards_tool): the body is accurate within a few millimetres of where it was
  // refined (docs/performance-details.md, "Refined where the tool aims"), so as the tool moves
  // over the organ the body is made again, refined where it aims now, while nothing touches it.
  /// Where the body was refined towards (m): the point where the tool's axis met the drawn
  /// surface as the scene opened, or at the last refineTowardsTool(); none unless the scene's
  /// tet mesh is refined towards the tool.
  const std::optional<Eigen::Vector3d>& refinementCentre() const { return m_refinementCentre; }
  /// The body would be refined again now: the tool's axis meets the organ more than
  /// kRefineAgainDistance_m from the refinement centre, and within kSteadyAimTravel_m of where
  /// it met it at the last check (the tool held over a site or moving along its axis), the tool
  /// at least kHapticRateNearClearance_m clear of the organ, and the body at rest
  /// (HapticRateBody::isAtRest); not within kRefineAgainDistance_m of where it could not be
  /// made. Checked every kRefinementCheckSteps steps, as of the last.
  bool wantsRefinementTowardsTool() const { return m_wantsRefinement; }
  static constexpr double kRefineAgainDistance_m = 0.004;
  static constexpr double kSteadyAimTravel_m = 0.0005;
  static constexpr long kRefinementCheckSteps = 16;
  /// The body made again from the scene's mesh, refined where the tool's axis meets the organ
  /// now (the caller pauses any loop stepping this simulation first): the geometry, the spring
  /// mesh (rebuilt in place), the body at rest on the new mesh. Time, events and the session's
  /// assessment go on (each spring's largest stretch taken from the old spring nearest it:
  /// SessionAssessment::takeUpMesh), and so does the softening the pokes left at the material
  /// points (HapticRateBody::takeUpSoftening). Views of the geometry and the spring mesh must be
  /// rebuilt.
  /// @returns false, changing nothing, where the tool's axis misses the organ or the scene is
  /// not refined towards the tool. @throws SceneFileError where the new body cannot be made
  /// (the simulation is left as it was).
  bool refineTowardsTool();
  /// Bodies made again so far (0 as the scene opens).
  long refinements() const { return m_refinements; }

 private:
  void record(const char* kind, const std::string& detail);
  /// Material, tables, spring mesh, laws, system and integrator from the parameters.
  void buildPhysics(const TissueParameters& parameters);
  /// m_startState: the rest state, let settle under gravity onto the supports when the scene
  /// has gravity (an event when it does not come to rest).
  void settle();
  /// The contacts of the coming step at m_state: the instrument's, then the tray's.
  void findContacts();
  /// step() with effects.model fem-haptic-rate: the probe's contact at this rate, the body's
  /// updates on their own thread (sim/HapticRateBody.h).
  StepOutcome stepHapticRate();
  /// The tool's clearance from the organ where the last step left both (sim/ToolClearance.h),
  /// exact within kHapticRateNearClearance_m.
  double toolClearance_m() const;
  /// wantsRefinementTowardsTool()'s conditions at the last step (the aim noted for the next).
  bool computeWantsRefinement();
  /// Records the conditions on now (each step's m_conditionsNow), their text built only then.
  template <typename Describe>
  void check(bool isOn, const char* kind, const Describe& describe) {
    if (!isOn) return;
    m_conditionsNow.push_back(kind);
    record(kind, describe());
  }

  SceneDescription m_scene;
  /// The scene's files as read, kept where the body is refined again where the tool aims.
  std::optional<SceneGeometry> m_readGeometry;
  SceneGeometry m_geometry;
  std::unique_ptr<TissueParameters> m_parameters;
  std::unique_ptr<StrainEnergy> m_energy;
  std::unique_ptr<StiffnessTable> m_table;
  std::unique_ptr<SpringMesh> m_springMesh;
  std::unique_ptr<SpringForceLaw> m_law;
  std::unique_ptr<ForkJoinPool> m_pool;  ///< the spring passes' threads (scene physics.threads)
  std::unique_ptr<SpringForceField> m_springs;
  std::unique_ptr<VolumeForceField> m_volume;            ///< effects.volume_cells cubes
  std::unique_ptr<NodalVolumeForceField> m_nodalVolume;  ///< effects.volume_cells nodes
  std::unique_ptr<TetIsochoricForceField> m_tets;        ///< effects.model fem
  /// The same with effects.strain_cells faces or nodes.
  std::unique_ptr<SmoothedStrainForceField> m_smoothedStrain;
  std::unique_ptr<HapticRateBody> m_hapticRate;  ///< effects.model fem-haptic-rate
  std::unique_ptr<MechanicalSystem> m_system;
  std::unique_ptr<TimeIntegrator> m_integrator;
  std::unique_ptr<SessionAssessment> m_assessment;
  std::size_t m_eventCount = 0;
  const char* m_latestEventKind = nullptr;
  std::unique_ptr<Grasp> m_grasp;                     ///< only with an instrument
  std::unique_ptr<ToolClearance> m_toolClearance;     ///< only with fem-haptic-rate's instrument
  std::unique_ptr<TraySupport> m_tray;                ///< only with a tray, not for fem-haptic-rate
  std::unique_ptr<PlaneFriction> m_friction;          ///< only with a tray that has friction
  std::vector<PlaneFriction::Anchor> m_startAnchors;  ///< where settling left the tray's grip
  ContactProvider* m_contact = nullptr;
  const InstrumentSource* m_instrument = nullptr;
  MechanicalState m_state;
  MechanicalState m_lastGoodState;  ///< after the last good step: what a corrupted state reverts to
  MechanicalState m_startState;
  std::vector<SofteningPeak> m_startStretchHistory;  ///< the Mullins memory settling left
  InstrumentPose m_pose;
  double m_timeStep_s;
  double m_stiffnessScale = 1.0;
  double m_bulkModulus_Pa = 0.0;
  double m_time_s = 0.0;
  long m_steps = 0;
  std::vector<InstabilityEvent> m_events;
  /// The kinds on at the last step (events fire on their onset).
  std::vector<std::string_view> m_activeConditions;
  std::vector<std::string_view> m_conditionsNow;  ///< scratch, capacity kept between steps
  std::optional<Eigen::Vector3d> m_refinementCentre;
  std::optional<Eigen::Vector3d> m_refusedAim;  ///< where the body could not be made again
  std::optional<Eigen::Vector3d> m_lastAim;     ///< where the tool aimed at the last check
  bool m_wantsRefinement = false;
  long m_refinements = 0;
};

}  // namespace tissuesim
