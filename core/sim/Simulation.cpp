// SPDX-License-Identifier: Apache-2.0
#include "sim/Simulation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "analysis/NetworkCalibration.h"
#include "analysis/UniaxialExperiment.h"
#include "fem/IsochoricSoftening.h"
#include "integrators/ImplicitEulerSolver.h"
#include "integrators/IntegratorChoice.h"
#include "material/TissueFile.h"
#include "sim/HapticRateBody.h"
#include "sim/HapticRateReach.h"
#include "sim/ToolClearance.h"
#include "sim/UnconvergedResidual.h"

namespace tissuesim {
namespace {
/// Events kept per run; past this only eventCount() grows.
constexpr std::size_t kMaxEvents = 100;
constexpr int kExtraNewtonIterations = 8;
// Settling under gravity (settle()): a step ten times the real-time one, damping near critical
// for an organ's slowest sag mode, still when no node moves faster than 0.1 mm/s, at most 5 s.
constexpr double kSettlingTimeStep_s = 0.01;
constexpr double kSettlingDamping_1_s = 20.0;
constexpr double kSettledSpeed_m_s = 1e-4;
constexpr int kSettlingMaxSteps = 500;
}  // namespace

namespace {
bool isRefinedTowardsTool(const SceneDescription& scene) {
  return scene.model == "fem-haptic-rate" && scene.tetMesh && scene.tetMesh->refinement;
}
}  // namespace

Simulation::Simulation(const SceneDescription& scene)
    : m_scene(scene),
      m_readGeometry(isRefinedTowardsTool(scene) ? std::optional(readSceneGeometry(scene))
                                                 : std::nullopt),
      m_geometry(m_readGeometry ? completeSceneGeometry(scene, *m_readGeometry)
                                : loadSceneGeometry(scene)),
      m_timeStep_s(scene.timeStep_s) {
  // The pose the body is made with (buildPhysics); the scene's start until a step moves it.
  if (scene.instrument) m_pose = {scene.instrument->tipStart_m, scene.instrument->direction, false};
  if (m_readGeometry) {
    Eigen::Vector3d centre;
    if (firstOrganCrossing(m_geometry, m_pose.tip_m, m_pose.direction, centre))
      m_refinementCentre = centre;
  }
  // The FEM at its own rate carries its tray in its own updates (sim/HapticRateBody.h).
  if (scene.tray && scene.model != "fem-haptic-rate")
    m_tray = std::make_unique<TraySupport>(m_geometry, *scene.tray);
  buildPhysics(loadTissueFile(scene.tissue));
  m_assessment = std::make_unique<SessionAssessment>(
      *m_springMesh,
      AssessmentThresholds{scene.assessment.toolForceThreshold_N,
                           scene.assessment.damageStretch.value_or(m_parameters->damageStretch)});
  m_assessment->setThreadPool(m_pool.get());
  settle();
  m_state = m_startState;
  m_lastGoodState = m_state;
  m_assessment->restart(m_pose.tip_m);
}

bool Simulation::refineTowardsTool() {
  if (!m_refinementCentre || !m_hapticRate || !m_readGeometry) return false;
  Eigen::Vector3d aim;
  if (!firstOrganCrossing(m_geometry, m_pose.tip_m, m_pose.direction, aim)) return false;
  // The scene's own mesh, refined where the tool aims now (as if the scene had started it there).
  SceneDescription aimed = m_scene;
  aimed.instrument->tipStart_m = m_pose.tip_m;
  aimed.instrument->direction = m_pose.direction;
  // Where the body cannot be made (a grading past the tets' limit there), it is not asked for
  // again until the tool aims elsewhere: the window would otherwise try every frame.
  m_refusedAim = aim;
  SceneGeometry geometry = completeSceneGeometry(aimed, *m_readGeometry);
  const SessionAssessment::SpringPeaks peaks = m_assessment->springPeaks();
  std::swap(m_geometry, geometry);
  // Made afresh, not continued from the old body (buildPhysics continues a body on the same mesh).
  std::unique_ptr<HapticRateBody> old = std::move(m_hapticRate);
  try {
    buildPhysics(*m_parameters);
  } catch (...) {
    std::swap(m_geometry, geometry);
    m_hapticRate = std::move(old);
    throw;
  }
  // What the trainee's pokes softened stays soft in the new body.
  m_hapticRate->takeUpSoftening(*old);
  old.reset();
  m_assessment->setThreadPool(m_pool.get());
  m_assessment->takeUpMesh(peaks);
  settle();
  m_state = m_startState;
  m_lastGoodState = m_state;
  m_refinementCentre = aim;
  m_refusedAim.reset();
  m_wantsRefinement = false;
  m_activeConditions.clear();
  ++m_refinements;
  return true;
}

bool Simulation::computeWantsRefinement() {
  Eigen::Vector3d aim;
  const bool isAiming = firstOrganCrossing(m_geometry, m_pose.tip_m, m_pose.direction, aim);
  // Steady: the aim moved little since the last check (the tool held over a site, or moving
  // along its axis towards it), so that a tool swept across the organ is not refined for at
  // every few millimetres of its way.
  const bool isSteady = isAiming && m_lastAim && (aim - *m_lastAim).norm() <= kSteadyAimTravel_m;
  m_lastAim = isAiming ? std::optional<Eigen::Vector3d>(aim) : std::nullopt;
  if (!isSteady || !m_hapticRate->isAtRest()) return false;
  if (toolClearance_m() < kHapticRateNearClearance_m) return false;
  return (aim - *m_refinementCentre).norm() > kRefineAgainDistance_m &&
         (!m_refusedAim || (aim - *m_refusedAim).norm() > kRefineAgainDistance_m);
}

void Simulation::replaceTissue(const TissueParameters& parameters) {
  const MechanicalState kept = m_state;
  const Eigen::Vector3d gravity = m_system->gravity.acceleration_m_s2;
  buildPhysics(parameters);
  m_assessment->setThreadPool(m_pool.get());
  // The damage done so far is judged against the new tissue's threshold (a scene's own stays).
  if (!m_scene.assessment.damageStretch) m_assessment->setDamageStretch(parameters.damageStretch);
  settle();  // the new tissue's own start (under the scene's gravity)
  m_system->gravity.acceleration_m_s2 = gravity;
  m_state = kept;
  m_lastGoodState = m_state;
  // The tray's grip starts afresh where the kept state touches it.
  if (m_friction) {
    m_friction->releaseAnchors();
    m_friction->acceptStep(m_state.x);
  }
  m_activeConditions.clear();
}

void Simulation::setSoftening(bool isOn) {
  m_scene.isSoftening = isOn;
  replaceTissue(TissueParameters(*m_parameters));
}

void Simulation::setGravity(const Eigen::Vector3d& gravity_m_s2) {
  m_system->gravity.acceleration_m_s2 = gravity_m_s2;
}
Eigen::Vector3d Simulation::gravity() const { return m_system->gravity.acceleration_m_s2; }

IntegratorSettings realTimeIntegratorSettings(const SceneDescription& scene) {
  IntegratorSettings settings;
  settings.massDamping_1_s = scene.massDamping_1_s;
  settings.maxIterations = scene.newtonIterations;
  settings.linearTolerance = scene.linearTolerance;
  settings.forceTolerance_N = 1e-6;
  // A step whose budget leaves a residual that counts as an event takes up to eight more
  // iterations first: few steps need them (a poke's hardest moments: the tissue springing back
  // against the retreating tool, contacts coming and going within the step, the organ slipping
  // off a shaft that drags it), and the physics loop's catch-up window absorbs them. Fewer left
  // such steps unconverged (docs/performance-details.md, "The integrators on the bundled poke").
  settings.extraIterations = kExtraNewtonIterations;
  settings.extraIterationResidual_N = kUnconvergedResidual_N;
  return settings;
}

void Simulation::buildPhysics(const TissueParameters& parameters) {
  const SceneDescription& scene = m_scene;
  // What can refuse the tissue is built first, aside: if it throws, the running physics is
  // untouched (the window keeps the old tissue after a bad file).
  auto newParameters = std::make_unique<TissueParameters>(parameters);
  auto energy = std::make_unique<StrainEnergy>(*newParameters);
  auto table = std::make_unique<StiffnessTable>(*energy);
  SpringMesh springMesh = buildSpringMesh(m_geometry.mesh, newParameters->density_kg_m3);
  const double bulkModulus_Pa = scene.bulkModulus_Pa;
  // The network's missing Poisson effect: scale V_e so a lattice's small-strain modulus is the
  // continuum's 3 mu0, measured once on the paper's specimen meshed with the same Kuhn lattice
  // the bundled meshes use (about 5.8). With the volume term, which resists the lattice's own
  // lateral contraction and so stiffens it most at small strain, that factor is refitted with
  // the term in place to the continuum's loading over the paper's cycles (a few per cent lower;
  // simulatorStiffnessScale, docs/scene-file.md "The volume term"). A scene can set
  // its own factor (effects.stiffness_scale) for meshes of another structure.
  // With the FEM the springs stay for the mesh's structure, the colour map's stretches and
  // the grasp, with no stiffness: the tets carry the elasticity.
  const bool isFem = scene.model == "fem";
  const bool isHapticRate = scene.model == "fem-haptic-rate";
  // The quadratic body at its own rate carries the elasticity and the volume (its dilatation per
  // tet at volume_term_kpa); the springs stay as with the FEM.
  std::unique_ptr<HapticRateBody> hapticRate;
  if (isHapticRate) {
    const SceneInstrument& tool = *scene.instrument;
    HapticRateBodySettings settings;
    settings.probeRadius_m = tool.shaftRadius_m;
    settings.latencySteps = std::lround(scene.femUpdateLatency_s / scene.timeStep_s);
    settings.newtonIterations = scene.newtonIterations;
    settings.gravity_m_s2 = scene.gravity_m_s2;
    settings.density_kg_m3 = newParameters->density_kg_m3;
    settings.letGoTravel_m = hapticRateToolSpeed_m_s(scene, *energy) * scene.timeStep_s;
    settings.reach_m = hapticRateReach_m(scene.newtonIterations, scene.bulkModulus_Pa,
                                         scene.gravity_m_s2.squaredNorm() > 0.0, *energy);
    // The body meets the probe on the surface the trainee sees (fem/CurvedBoundary.h).
    if (m_geometry.surface) settings.drawnSurface = &*m_geometry.surface;
    // The same softening as the springs', per material point, its onset rounded for the
    // updates' Newton iterations (fem/IsochoricSoftening.h).
    if (scene.isSoftening && StressSoftening(*newParameters).isEnabled())
      settings.softening.emplace(*newParameters, kIsochoricSofteningOnsetMeasure);
    if (scene.tray)
      settings.tray =
          HapticRateTray{scene.tray->up, scene.tray->height_m, scene.tray->stiffness_Pa_per_m};
    // The probe where the scene starts it, or, for a body made again where the tool aims
    // (refineTowardsTool, the tool clear of the organ), where it is; a new tissue's body takes
    // the probe up from the old one's below.
    const InstrumentPose made =
        m_hapticRate ? InstrumentPose{tool.tipStart_m, tool.direction, false} : m_pose;
    const Eigen::Vector3d tip = made.tip_m - tool.shaftRadius_m * made.direction;
    try {
      hapticRate = std::make_unique<HapticRateBody>(
          m_geometry.mesh, m_geometry.fixedNodes, scene.fixed.box_m, *energy, scene.bulkModulus_Pa,
          settings, tip, tip - tool.shaftLength_m * made.direction);
    } catch (const std::invalid_argument& error) {
      throw SceneFileError(scene.source.string() +
                           ": effects.model fem-haptic-rate: " + error.what());
    }
    // A new tissue: the body goes on from where the old material had it, the probe pressing on.
    if (m_hapticRate) {
      const Eigen::Vector3d centre = m_pose.tip_m - tool.shaftRadius_m * m_pose.direction;
      hapticRate->continueFrom(*m_hapticRate, centre,
                               centre - tool.shaftLength_m * m_pose.direction);
    }
  }
  const double stiffnessScale = isFem || isHapticRate ? 0.0
                                : scene.stiffnessScale > 0.0
                                    ? scene.stiffnessScale
                                    : simulatorStiffnessScale(*energy, *table, bulkModulus_Pa);
  springMesh.volume_m3 *= stiffnessScale;

  // Dependents first: each holds references into the ones before it.
  m_hapticRate.reset();
  m_integrator.reset();
  m_system.reset();
  m_friction.reset();
  m_tets.reset();
  m_smoothedStrain.reset();
  m_nodalVolume.reset();
  m_volume.reset();
  m_springs.reset();
  m_law.reset();
  m_grasp.reset();
  m_parameters = std::move(newParameters);
  m_energy = std::move(energy);
  m_table = std::move(table);
  m_hapticRate = std::move(hapticRate);
  m_stiffnessScale = stiffnessScale;
  m_bulkModulus_Pa = bulkModulus_Pa;
  // Rebuilt in place: views of the scene keep a reference to the spring mesh across a new tissue.
  if (m_springMesh) {
    *m_springMesh = std::move(springMesh);
  } else {
    m_springMesh = std::make_unique<SpringMesh>(std::move(springMesh));
  }
  const SpringLaw law = springLawNamed(scene.springLaw).value_or(SpringLaw::Eesm);
  // smm's one stiffness is fitted only when the scene asks for that law (start-up does no work a
  // scene does not need).
  const double linearModulus = UniaxialExperiment::springLawLinearModulus(law, *m_energy, *m_table);
  m_law = std::make_unique<SpringForceLaw>(law, *m_table, *m_parameters, linearModulus,
                                           scene.isSoftening);
  m_springs = std::make_unique<SpringForceField>(*m_springMesh, *m_law);
  if (scene.threads > 1) {
    m_pool = std::make_unique<ForkJoinPool>(scene.threads);
    m_springs->setThreadPool(m_pool.get());
  }
  const bool isNodal = scene.volumeCells == "nodes";
  const bool hasVolumeTerm = bulkModulus_Pa > 0.0 && !isHapticRate;
  if (hasVolumeTerm && !isNodal) {
    m_volume = std::make_unique<VolumeForceField>(*m_springMesh, bulkModulus_Pa);
    m_volume->setThreadPool(m_pool.get());
  }
  m_system = std::make_unique<MechanicalSystem>(*m_springs, m_volume.get());
  if (hasVolumeTerm && isNodal) {
    m_nodalVolume = std::make_unique<NodalVolumeForceField>(m_springMesh->restPositions_m,
                                                            m_springMesh->tets, bulkModulus_Pa);
    m_nodalVolume->setThreadPool(m_pool.get());
    m_system->addField(*m_nodalVolume);
  }
  if (isFem && scene.strainCells != "tets") {
    const TetMesh& mesh = m_geometry.mesh;
    m_smoothedStrain = std::make_unique<SmoothedStrainForceField>(
        scene.strainCells == "faces" ? faceStrainCells(mesh.nodes_m, mesh.tets)
                                     : nodeStrainCells(mesh.nodes_m, mesh.tets),
        mesh.nodeCount(), *m_energy);
    m_smoothedStrain->setThreadPool(m_pool.get());
    m_system->addField(*m_smoothedStrain);
  } else if (isFem) {
    m_tets = std::make_unique<TetIsochoricForceField>(m_geometry.mesh.nodes_m, m_geometry.mesh.tets,
                                                      *m_energy);
    m_tets->setThreadPool(m_pool.get());
    m_system->addField(*m_tets);
  }
  m_system->gravity.acceleration_m_s2 = scene.gravity_m_s2;
  if (m_tray && scene.tray->friction > 0.0) {
    m_friction = std::make_unique<PlaneFriction>(m_tray->points(), m_tray->up(), m_tray->height_m(),
                                                 scene.tray->friction, m_springMesh->nodeCount());
    m_system->addField(*m_friction);
  }
  // The instrument's few contacts and every tray point at once, without allocating.
  if (m_tray) m_system->contacts.reserve(256 + static_cast<std::size_t>(m_tray->pointCount()));
  for (const int node : m_geometry.fixedNodes) m_system->fixNode(node);

  m_integrator = makeIntegrator(scene.integrator, realTimeIntegratorSettings(scene));
  if (scene.instrument && !isHapticRate) {
    // The grasper reaches surface nodes within two shaft radii of the tip.
    m_grasp = std::make_unique<Grasp>(faceNodes(boundaryFaces(m_geometry.mesh)),
                                      2.0 * scene.instrument->shaftRadius_m);
  }
  // The FEM at its own rate grasps its own surface; its tool slows by its clearance from the
  // organ (sim/ToolProxy.h's near speed).
  if (scene.instrument && isHapticRate)
    m_toolClearance = std::make_unique<ToolClearance>(m_geometry.mesh);
}

double Simulation::toolClearance_m() const {
  if (!m_toolClearance) return std::numeric_limits<double>::infinity();
  const SceneInstrument& tool = *m_scene.instrument;
  const Eigen::Vector3d centre = m_pose.tip_m - tool.shaftRadius_m * m_pose.direction;
  const Eigen::Vector3d top = centre - tool.shaftLength_m * m_pose.direction;
  return (*m_toolClearance)(m_state.x, centre, top, tool.shaftRadius_m, kHapticRateNearClearance_m);
}

std::vector<int> Simulation::heldNodes() const {
  if (m_hapticRate) return m_hapticRate->heldCorners();
  return m_grasp ? m_grasp->heldNodes() : std::vector<int>{};
}

const char* eventKindWords(const char* kind) {
  static constexpr std::pair<std::string_view, const char*> kWords[] = {
      {"refused", "a step refused"},
      {"outrun", "an FEM update could not follow the probe"},
      {"non-finite", "a non-finite step, rolled back"},
      {"unconverged", "a step left unconverged"},
      {"locking", "springs past locking"},
      {"collapsed", "springs of zero length"},
      {"inverted", "inverted tets"},
      {"unsettled", "the organ did not settle"},
  };
  for (const auto& [known, words] : kWords) {
    if (known == kind) return words;
  }
  return kind;
}

std::map<std::string, int> countEventsByKind(const std::vector<InstabilityEvent>& events) {
  std::map<std::string, int> counts;
  for (const InstabilityEvent& event : events) ++counts[event.kind];
  return counts;
}

std::string eventKindSummary(const std::vector<InstabilityEvent>& events) {
  std::string summary;
  for (const auto& [kind, count] : countEventsByKind(events))
    summary += (summary.empty() ? "" : ", ") + std::to_string(count) + " " + kind;
  return summary;
}

Simulation::~Simulation() = default;

void Simulation::settle() {
  m_startState = m_system->restState();
  m_springs->resetStretchHistory();
  m_startStretchHistory = m_springs->stretchHistory();
  if (m_friction) {
    m_friction->releaseAnchors();
    m_startAnchors = m_friction->anchors();
  }
  // The quadratic body at its own rate came to balance under its weight on the tray as it was
  // made: the springs, which carry no force with it, take its corners.
  if (m_hapticRate) {
    m_startState.x = m_hapticRate->startCorners();
    return;
  }
  if (m_scene.gravity_m_s2.squaredNorm() == 0.0) return;
  // Long, heavily damped implicit steps: backward Euler is stable at any step, and the damping
  // (about twice the slowest sag mode's angular frequency, a few rad/s on an organ) brings the
  // organ to rest within a second or two of simulated time, in under a couple of hundred steps.
  IntegratorSettings settings;
  settings.massDamping_1_s = kSettlingDamping_1_s;
  // Two iterations a step and a loose linear tolerance: what is left of one step's residual is
  // taken up by the next, and only where the organ comes to rest matters (one iteration did not
  // bring the bundled liver to rest in 5 s).
  settings.maxIterations = 2;
  settings.linearTolerance = 1e-4;
  ImplicitEulerSolver settler(settings, LinearSolverKind::ConjugateGradient);
  MechanicalState state = m_startState;
  double speed_m_s = std::numeric_limits<double>::infinity();
  int step = 0;
  bool isSettled = false;
  for (; step < kSettlingMaxSteps && !isSettled; ++step) {
    m_system->contacts.clear();
    if (m_tray) m_tray->findContacts(state.x, m_system->contacts);
    if (m_friction) m_friction->beginStep(state.x);
    const StepReport report = settler.step(*m_system, state, kSettlingTimeStep_s);
    if (report.refused || !report.isFinite) break;
    if (m_friction) m_friction->acceptStep(state.x);
    speed_m_s = state.v.colwise().norm().maxCoeff();
    isSettled = speed_m_s < kSettledSpeed_m_s;
  }
  m_system->contacts.clear();
  if (!isSettled) {
    m_springs->resetStretchHistory();
    if (m_friction) m_friction->releaseAnchors();
    std::ostringstream detail;
    detail << "the organ did not come to rest under gravity in " << step * kSettlingTimeStep_s
           << " s (fastest node " << speed_m_s << " m/s); starting from the unloaded shape";
    record("unsettled", detail.str());
    return;
  }
  state.v.setZero();
  m_startState = state;
  // The organ's own weight has preconditioned it (the first loading of the Mullins effect):
  // that memory belongs to the start state, and a reset restores it with the positions.
  m_startStretchHistory = m_springs->stretchHistory();
  // So has the tray's grip: where the organ came to rest on it.
  if (m_friction) m_startAnchors = m_friction->anchors();
}

void Simulation::reset() {
  m_state = m_startState;
  m_lastGoodState = m_state;
  m_springs->restoreStretchHistory(m_startStretchHistory);
  if (m_friction) m_friction->restoreAnchors(m_startAnchors);
  m_time_s = 0.0;
  m_steps = 0;
  m_events.clear();
  m_eventCount = 0;
  m_latestEventKind = nullptr;
  m_activeConditions.clear();
  if (m_grasp) m_grasp->release();
  if (m_hapticRate) m_hapticRate->reset();
  m_assessment->restart(m_pose.tip_m);
}

void Simulation::record(const char* kind, const std::string& detail) {
  if (std::find(m_activeConditions.begin(), m_activeConditions.end(), std::string_view(kind)) !=
      m_activeConditions.end()) {
    return;
  }
  ++m_eventCount;
  m_latestEventKind = kind;
  if (m_events.size() < kMaxEvents) m_events.push_back({m_steps, m_time_s, kind, detail});
}

void Simulation::findContacts() {
  m_system->contacts.clear();
  if (m_contact != nullptr && m_scene.instrument)
    m_contact->findContacts(m_state.x, m_pose, m_system->contacts);
  if (m_tray) m_tray->findContacts(m_state.x, m_system->contacts);
  if (m_friction) m_friction->beginStep(m_state.x);
}

StepOutcome Simulation::step() {
  StepOutcome outcome;
  // The integrators never leave a non-finite state behind, so one here came from elsewhere (a
  // bug, memory gone bad): the last good state is put back before anything reads it.
  if (!m_state.isFinite()) {
    m_state = m_lastGoodState;  // same sizes: no allocation
    record("non-finite", "the state held a value that is not finite; the last good state (t = " +
                             std::to_string(m_time_s) + " s) was put back");
  }
  if (m_hapticRate) return stepHapticRate();
  const double next = m_time_s + m_timeStep_s;
  if (m_instrument != nullptr) m_pose = m_instrument->poseAt(next);
  findContacts();
  if (m_grasp) m_grasp->apply(m_state.x, m_pose, m_system->contacts);
  outcome.integrator = m_integrator->step(*m_system, m_state, m_timeStep_s);
  // What the instrument feels: the contacts at the state the step reached (the last good one
  // after a failed step), the grasp's pull among them.
  outcome.contact = m_system->contacts.reaction(m_state.x, m_pose.tip_m);
  // Where the contacts were impulses, their mean force over the step is what the tool felt:
  // k delta at the step's end reads low, the impulses having pushed the surface back already.
  const std::optional<Eigen::Vector3d>& impulse = outcome.integrator.toolImpulse_Ns;
  if (impulse && outcome.integrator.isFinite) outcome.contact.toolForce_N = *impulse / m_timeStep_s;
  outcome.isGood = !outcome.integrator.refused && outcome.integrator.isFinite;
  outcome.maxStretch = outcome.integrator.forces.springs.maxStretch;

  // Conditions are checked every step; their text is built only when one is on, so a quiet
  // step allocates nothing here.
  m_conditionsNow.clear();
  const StepReport& r = outcome.integrator;
  check(r.refused, "refused", [&] { return r.reason; });
  check(!r.isFinite, "non-finite", [&] { return r.reason; });
  // A real-time step stops at its iteration budget; only a residual that matters is an event.
  const double load_N = outcome.contact.toolForce_N.norm();
  check(!r.converged && r.isFinite && isUnconvergedResidual(r.residual_N, load_N), "unconverged",
        [&] {
          return "residual " + std::to_string(r.residual_N) + " N under an instrument force of " +
                 std::to_string(load_N) + " N (start " + std::to_string(r.initialResidual_N) + ")";
        });
  // The FEM's tets carry the material; its inert springs only measure stretch.
  if (m_tets || m_smoothedStrain) {
    check(r.forces.tets.beyondRangeCount > 0, "locking", [&] {
      return std::to_string(r.forces.tets.beyondRangeCount) + (m_tets ? " tets" : " strain cells") +
             " past the usable range";
    });
  } else {
    check(r.forces.springs.beyondRangeCount > 0, "locking", [&] {
      return std::to_string(r.forces.springs.beyondRangeCount) +
             " springs past the usable stretch range";
    });
  }
  check(r.forces.springs.collapsedCount > 0, "collapsed", [&] {
    return std::to_string(r.forces.springs.collapsedCount) + " springs of zero length";
  });
  // Without the volume term nothing else counts inverted tets: look (O(#T), 30 us at the liver's
  // size on one thread; on the pool).
  const int inverted =
      m_volume || m_nodalVolume
          ? r.forces.volume.invertedTetCount
          : VolumeForceField::inspect(*m_springMesh, m_state.x, m_pool.get()).invertedTetCount;
  check(inverted > 0, "inverted", [&] { return std::to_string(inverted) + " inverted tets"; });
  m_activeConditions.swap(m_conditionsNow);  // a condition that ended may fire again when it recurs

  if (outcome.isGood) {
    if (m_friction) m_friction->acceptStep(m_state.x);
    m_time_s = next;
    ++m_steps;
    m_lastGoodState.x = m_state.x;  // same sizes: copies, no allocation
    m_lastGoodState.v = m_state.v;
    m_assessment->addStep(m_state.x, m_pose.tip_m, outcome.contact.toolForce_N.norm(),
                          m_timeStep_s);
  }
  return outcome;
}

StepOutcome Simulation::stepHapticRate() {
  StepOutcome outcome;
  const double next = m_time_s + m_timeStep_s;
  if (m_instrument != nullptr) {
    if (m_instrument->takesClearance()) m_instrument->noteClearance(toolClearance_m());
    m_pose = m_instrument->poseAt(next);
  }
  const SceneInstrument& tool = *m_scene.instrument;
  const Eigen::Vector3d centre = m_pose.tip_m - tool.shaftRadius_m * m_pose.direction;
  const HapticRateStep haptic = m_hapticRate->step(
      centre, centre - tool.shaftLength_m * m_pose.direction, m_state.x, m_pose.isGrasping);
  outcome.contact.toolForce_N = haptic.probeForce_N;
  outcome.integrator.converged = haptic.isSettled;
  outcome.integrator.iterations = haptic.contactIterations;

  m_conditionsNow.clear();
  check(!haptic.isSettled, "unconverged", [&] {
    return "the probe's contact stopped short of its tolerance after " +
           std::to_string(haptic.contactIterations) + " iterations (" +
           std::to_string(haptic.candidates) + " surface nodes), " +
           std::to_string(haptic.contactResidual_N) + " N left on a node";
  });
  check(haptic.isUpdateRefused, "outrun", [&] {
    return "an FEM update was refused (" + m_hapticRate->updateProblem() +
           "); the contact in use is kept until one is not";
  });
  check(haptic.isPassedThrough, "outrun",
        [&] { return "an FEM update found " + m_hapticRate->updateProblem(); });
  const int inverted =
      VolumeForceField::inspect(*m_springMesh, m_state.x, m_pool.get()).invertedTetCount;
  check(inverted > 0, "inverted", [&] { return std::to_string(inverted) + " inverted tets"; });
  m_activeConditions.swap(m_conditionsNow);

  m_time_s = next;
  ++m_steps;
  m_lastGoodState.x = m_state.x;
  // The springs carry no force here; the assessment measures their stretch all the same.
  outcome.maxStretch = m_assessment->addStep(m_state.x, m_pose.tip_m,
                                             outcome.contact.toolForce_N.norm(), m_timeStep_s);
  if (m_refinementCentre && m_steps % kRefinementCheckSteps == 0)
    m_wantsRefinement = computeWantsRefinement();
  return outcome;
}

}  // namespace tissuesim
