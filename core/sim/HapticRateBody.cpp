// SPDX-License-Identifier: Apache-2.0
#include "sim/HapticRateBody.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <limits>
#include <stdexcept>
#include <utility>

#include <Eigen/Geometry>

#include "fem/QuadraticTetWeight.h"
#include "fem/SampledSurface.h"
#include "mesh/TetLocator.h"
#include "sim/UnconvergedResidual.h"

namespace tissuesim {
namespace {

/// 3 #V flags: the fixed corners, each edge's midpoint between two of them, and every node in
/// the fixed box (a midpoint there too: the FEM reference holds all its nodes in the box).
std::vector<char> fixedDofs(const QuadraticTetMesh& mesh, const std::vector<int>& fixedNodes,
                            const std::optional<Eigen::AlignedBox3d>& fixedBox_m) {
  std::vector<char> isFixedNode(static_cast<std::size_t>(mesh.nodeCount()), 0);
  for (const int node : fixedNodes) {
    if (node < 0 || node >= mesh.cornerCount)
      throw std::invalid_argument("HapticRateBody: a fixed node is not the mesh's");
    isFixedNode[static_cast<std::size_t>(node)] = 1;
  }
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    for (int e = 0; e < 6; ++e) {
      const auto a = static_cast<std::size_t>(mesh.tets(kQuadraticTetEdges[e][0], t));
      const auto b = static_cast<std::size_t>(mesh.tets(kQuadraticTetEdges[e][1], t));
      if (isFixedNode[a] && isFixedNode[b])
        isFixedNode[static_cast<std::size_t>(mesh.tets(4 + e, t))] = 1;
    }
  }
  if (fixedBox_m) {
    for (Eigen::Index i = 0; i < mesh.nodeCount(); ++i) {
      if (fixedBox_m->contains(mesh.nodes_m.col(i))) isFixedNode[static_cast<std::size_t>(i)] = 1;
    }
  }
  std::vector<char> isFixed(3 * isFixedNode.size(), 0);
  for (std::size_t i = 0; i < isFixedNode.size(); ++i) {
    if (isFixedNode[i]) std::fill_n(isFixed.begin() + static_cast<std::ptrdiff_t>(3 * i), 3, 1);
  }
  return isFixed;
}

}  // namespace

HapticRateBody::HapticRateBody(const TetMesh& mesh, const std::vector<int>& fixedNodes,
                               const std::optional<Eigen::AlignedBox3d>& fixedBox_m,
                               const StrainEnergy& energy, double bulkModulus_Pa,
                               const HapticRateBodySettings& settings, const Eigen::Vector3d& tip_m,
                               const Eigen::Vector3d& top_m)
    : m_settings(settings), m_mesh(makeQuadraticTetMesh(mesh)) {
  if (!(settings.probeRadius_m > 0.0) || !(settings.contactSpacing_m > 0.0) ||
      !(settings.pressureStiffness_Pa_m > 0.0) || settings.latencySteps < 0)
    throw std::invalid_argument(
        "HapticRateBody: the probe's radius, the spacing and the penalty must be > 0, the "
        "latency >= 0");
  if (settings.drawnSurface != nullptr)
    m_curvedBoundary = curveBoundaryOnto(m_mesh, mesh, *settings.drawnSurface);
  std::vector<CapsulePenalty::Point> points =
      sampleSurfacePoints(m_mesh, quadraticSurfacePieces(mesh, m_mesh), settings.contactSpacing_m,
                          settings.pressureStiffness_Pa_m, Eigen::Vector3d::Zero(),
                          std::numeric_limits<double>::infinity());
  m_surfacePoints = points.size();
  m_model = std::make_unique<FemModel>(m_mesh, energy, bulkModulus_Pa);
  if (m_settings.softening) m_model->setSoftening(&*m_settings.softening);
  if (settings.gravity_m_s2.squaredNorm() > 0.0) {
    m_weight = quadraticTetWeight(m_mesh, settings.density_kg_m3, settings.gravity_m_s2);
    m_support.terms.push_back(&m_weight);
  }
  if (settings.tray) {
    if (!(settings.tray->stiffness_Pa_per_m > 0.0))
      throw std::invalid_argument("HapticRateBody: the tray's stiffness must be > 0");
    // The tray's points: the probe's, with the tray's penalty per unit area.
    std::vector<CapsulePenalty::Point> trayPoints = points;
    for (CapsulePenalty::Point& point : trayPoints) {
      point.stiffness_N_m *= settings.tray->stiffness_Pa_per_m / settings.pressureStiffness_Pa_m;
    }
    m_tray = std::make_unique<PlanePenalty>(std::move(trayPoints), settings.tray->up,
                                            settings.tray->height_m);
    m_support.terms.push_back(m_tray.get());
  }
  m_fem = std::make_unique<HapticRateFem>(*m_model, fixedDofs(m_mesh, fixedNodes, fixedBox_m),
                                          std::move(points), settings.candidateMargin_m,
                                          settings.newtonIterations, &m_support);
  const HapticRateUpdate start = m_fem->settle(tip_m, top_m, settings.probeRadius_m, m_start);
  if (!start.hasNext) {
    throw std::invalid_argument(
        m_support.terms.empty()
            ? "HapticRateBody: the body at rest has no definite Hessian"
            : "HapticRateBody: the body does not come to balance under its weight (" +
                  std::to_string(start.residual_N) + " N left on a node after " +
                  std::to_string(HapticRateFem::kSettlingIterations) + " Newton iterations)");
  }
  m_startCorners = m_fem->positions().leftCols(m_mesh.cornerCount);
  if (m_tray) m_startTraySupport_N = m_tray->support_N(m_fem->positions());
  restartSettled();
  m_worker = std::thread([this] { work(); });
}

HapticRateBody::~HapticRateBody() {
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_shouldStop = true;
  }
  m_wake.notify_all();
  m_worker.join();
}

std::string refusedUpdateReason(double residual_N, double travel_m, double reach_m) {
  char figures[256];
  int length = std::snprintf(figures, sizeof figures,
                             "its Newton iterations left %.3g N out of balance, the probe moved "
                             "%.2f mm since the update before started",
                             residual_N, 1e3 * travel_m);
  if (reach_m > 0.0 && length > 0 && static_cast<std::size_t>(length) < sizeof figures) {
    std::snprintf(figures + length, sizeof figures - static_cast<std::size_t>(length),
                  " (an update follows %.2f mm)", 1e3 * reach_m);
  }
  // A tool held to its limit travels the reach an update to round-off.
  if (reach_m > 0.0 && travel_m <= reach_m * (1.0 + 1e-6)) {
    return std::string(figures) +
           ": the body moved further than one update follows (pressed deep, where the tissue is "
           "stiffer than where the reach was measured, or sliding off the frictionless probe)";
  }
  return std::string(figures) + ": the probe moved further than one update can follow";
}

void HapticRateBody::work() {
  std::unique_lock<std::mutex> lock(m_mutex);
  for (;;) {
    m_wake.wait(lock, [this] { return m_hasJob || m_shouldStop; });
    if (m_shouldStop) return;
    lock.unlock();
    const auto started = std::chrono::steady_clock::now();
    HapticRateUpdate report;
    std::string error;
    try {
      const bool isFromContact = m_jobHasBody && !m_jobGoesOn;
      m_fem->setHeldPoints(m_jobHeld);
      report = m_fem->update(isFromContact ? &m_jobBody : nullptr, m_jobCandidates, m_jobForces,
                             m_jobTip, m_jobTop, m_settings.probeRadius_m, *m_next);
      if (report.isOutOfBalance) {
        error = refusedUpdateReason(report.residual_N, m_jobTravel_m, m_settings.reach_m);
      } else if (!report.hasNext) {
        error = "no definite Hessian within reach of the body's state";
      } else if (report.isPassedThrough) {
        error =
            "the probe had passed through the surface it pressed: it moved further than "
            "the updates follow";
      }
    } catch (const std::exception& e) {  // the haptic loop keeps its contact; the reason is kept
      report.hasNext = false;
      error = e.what();
    }
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    lock.lock();
    m_jobReport = report;
    m_jobWall_s = wall_s;
    m_jobError = std::move(error);
    m_hasJob = false;
    m_isJobDone = true;
    m_done.notify_all();
  }
}

void HapticRateBody::startUpdate(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m) {
  // The worker is idle: the job's fields are the haptic thread's until the job is posted. They
  // take the contact's last settled state; where that contact is the one the worker is about to
  // overwrite, the job's fields keep it for the updates after this one.
  if (m_settledOwner != nullptr) {
    m_jobHasBody = settledState(m_jobBody, m_jobCandidates, m_jobForces);
    if (m_settledOwner == m_next) m_settledOwner = nullptr;
  }
  // After a refused update the next one goes on from where that one's Newton iterations ended
  // (the FEM's own state), nearer the balance: from the kept contact's body again, under the same
  // forces, it would repeat the refused one exactly.
  m_jobGoesOn = m_isRefusing;
  m_jobHeld = m_heldPoints;
  m_jobTravel_m = m_hasJobTip ? (tip_m - m_jobTip).norm() : 0.0;
  m_hasJobTip = true;
  m_jobTip = tip_m;
  m_jobTop = top_m;
  m_stepsSinceUpdate = 0;
  m_isInFlight = true;
  ++m_updatesStarted;
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_hasJob = true;
    m_isJobDone = false;
  }
  m_wake.notify_all();
}

bool HapticRateBody::wouldRepeatLastUpdate(const Eigen::Vector3d& tip_m,
                                           const Eigen::Vector3d& top_m) const {
  // The grasp's targets move the held points every step, and the opening jaws lead them back.
  if (!m_heldPoints.empty() || m_letGoSteps > 0) return false;
  // A probe still to round-off (a script's held pose interpolated) has not moved; one that
  // moves changes the load it presses with, or, free of the body, the points near it.
  if ((tip_m - m_jobTip).norm() > kRestingProbeTravel_m ||
      (top_m - m_jobTop).norm() > kRestingProbeTravel_m || m_settledOwner == nullptr)
    return false;
  if (m_settledOwner->candidates() != m_jobCandidates) return false;
  // The next update's Newton would start with at most the last one's residual plus the change
  // in load: within the tolerance it takes no iteration, and linearises the body where it is.
  const double loadChange_N =
      m_settledForces.size() > 0 ? (m_settledForces - m_jobForces).cwiseAbs().maxCoeff() : 0.0;
  return m_lastResidual_N + loadChange_N <= HapticRateFem::kSolverTolerance_N;
}

bool HapticRateBody::settledState(Eigen::Matrix3Xd& body_m, std::vector<int>& candidates,
                                  Eigen::Matrix3Xd& forces_N) const {
  if (m_settledOwner == nullptr) {  // the job's fields hold it (startUpdate)
    body_m = m_jobBody;
    candidates = m_jobCandidates;
    forces_N = m_jobForces;
    return m_jobHasBody;
  }
  const bool hasBody = m_settledOwner->hasBody();
  if (hasBody) {
    body_m.resize(3, m_mesh.nodeCount());
    m_settledOwner->firstBodyPositions(m_settledForces, body_m);
  }
  candidates = m_settledOwner->candidates();
  forces_N = m_settledForces;
  return hasBody;
}

void HapticRateBody::takeUpSoftening(HapticRateBody& other) {
  if (!m_settings.softening || !other.m_settings.softening) return;
  if (other.m_isInFlight) other.waitForUpdate();  // its worker writes nothing read here now
  const std::vector<double> otherPeaks = other.m_model->peakShifts();
  const Eigen::Matrix3Xd otherPoints = other.m_model->energyPointsAtRest();
  const Eigen::Index pointsPerTet = otherPoints.cols() / other.m_mesh.tetCount();
  TetMesh otherCorners;
  otherCorners.nodes_m = other.m_mesh.nodes_m.leftCols(other.m_mesh.cornerCount);
  otherCorners.tets = other.m_mesh.tets.topRows<4>();
  const TetLocator locator(otherCorners);
  std::vector<double> peaks = m_model->peakShifts();
  const Eigen::Matrix3Xd points = m_model->energyPointsAtRest();
  for (Eigen::Index p = 0; p < points.cols(); ++p) {
    const int tet = locator.locate(points.col(p)).tet;
    double nearest_m = std::numeric_limits<double>::infinity();
    double peak = 0.0;
    for (Eigen::Index q = pointsPerTet * tet; q < pointsPerTet * (tet + 1); ++q) {
      const double distance_m = (otherPoints.col(q) - points.col(p)).norm();
      if (distance_m < nearest_m) {
        nearest_m = distance_m;
        peak = otherPeaks[static_cast<std::size_t>(q)];
      }
    }
    double& own = peaks[static_cast<std::size_t>(p)];
    own = std::max(own, peak);
  }
  m_model->setPeakShifts(peaks);
}

void HapticRateBody::continueFrom(HapticRateBody& other, const Eigen::Vector3d& tip_m,
                                  const Eigen::Vector3d& top_m) {
  if (other.nodeCount() != nodeCount() || other.m_mesh.cornerCount != m_mesh.cornerCount)
    throw std::invalid_argument("HapticRateBody: another mesh's body to continue from");
  if (other.m_isInFlight) other.waitForUpdate();  // its worker writes nothing read here now
  Eigen::Matrix3Xd body_m, forces_N;
  std::vector<int> candidates;
  const bool hasBody = other.settledState(body_m, candidates, forces_N);
  // This body's worker is idle (no update posted yet): its FEM is the caller's until then. The
  // new material linearised where the old one had the body, with no load: the contact then finds
  // the forces that hold it there with this material (twice the old ones for a material twice
  // as stiff). Under the old forces instead, a stiffer body springs back from under the probe by
  // more than an update follows.
  HapticRateUpdate report;
  report.hasNext = false;
  // The strains the old material reached are this one's history too.
  const std::vector<double> peaks = other.m_model->peakShifts();
  m_model->setPeakShifts(peaks);
  if (hasBody)
    report = m_fem->linearizeAt(body_m, tip_m, top_m, m_settings.probeRadius_m, *m_inUse);
  if (!report.hasNext) {
    // The old body free of the probe (its contact has no body), or a state the new material
    // cannot take up: from rest, as before, the history kept (the peaks are strains).
    m_fem->restart();
    m_model->setPeakShifts(peaks);
    restartSettled();
    return;
  }
  if (other.m_settledOwner != nullptr) m_inUse->startFrom(*other.m_settledOwner);
  m_settledOwner = m_inUse;
  m_settledForces.setZero(3, static_cast<Eigen::Index>(m_inUse->candidates().size()));
  m_settledCorners = other.m_settledCorners;
  m_settledProbeForce_N = other.m_settledProbeForce_N;
  m_lastResidual_N = std::numeric_limits<double>::infinity();
}

void HapticRateBody::waitForUpdate() {
  std::unique_lock<std::mutex> lock(m_mutex);
  m_done.wait(lock, [this] { return m_isJobDone; });
}

HapticRateStep HapticRateBody::step(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m,
                                    Eigen::Matrix3Xd& corners_m, bool isGrasping) {
  HapticRateStep outcome;
  m_lastWait_s = 0.0;
  if (m_isInFlight) {
    bool isTaken = false;
    if (m_settings.latencySteps > 0) {
      isTaken = m_stepsSinceUpdate >= m_settings.latencySteps;
      if (isTaken) {
        const auto waiting = std::chrono::steady_clock::now();
        waitForUpdate();
        m_lastWait_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - waiting).count();
      }
    } else {
      std::lock_guard<std::mutex> lock(m_mutex);
      isTaken = m_isJobDone;
    }
    if (isTaken) {
      m_isInFlight = false;
      ++m_updatesTaken;
      m_updating_s += m_jobWall_s;
      m_isPassedThrough = m_jobReport.isPassedThrough;
      m_lastResidual_N = m_jobReport.hasNext && !m_jobReport.isPassedThrough
                             ? m_jobReport.residual_N
                             : std::numeric_limits<double>::infinity();
      if (m_isPassedThrough) m_updateProblem = m_jobError;
      if (m_jobReport.hasNext) {
        m_next->startFrom(*m_inUse);
        std::swap(m_inUse, m_next);
        attachHeld(*m_inUse);
        m_isRefusing = false;
      } else {
        m_isRefusing = true;
        m_updateProblem = m_jobError;
      }
    }
  }
  if (isGrasping && !m_wasGrasping) {
    m_letGoSteps = 0;
    grasp(tip_m, top_m);
  }
  if (!isGrasping && m_wasGrasping && !m_heldPoints.empty()) startLettingGo(tip_m, top_m);
  m_wasGrasping = isGrasping;
  if (m_letGoSteps > 0) {
    leadHeldBack();
  } else if (!m_inUseHeld.empty()) {
    const Eigen::Matrix3d turn = shaftTurn(tip_m, top_m);
    for (std::size_t h = 0; h < m_inUseHeld.size(); ++h) {
      m_inUse->heldTargets().col(static_cast<Eigen::Index>(h)) =
          tip_m + turn * m_heldOffsets_m.col(m_inUseHeld[h]);
    }
  }
  const Eigen::Vector3d reaction = m_inUse->solve(tip_m, top_m, m_settings.probeRadius_m);
  outcome.contactResidual_N = m_inUse->residual_N();
  outcome.isSettled =
      m_inUse->converged() || !isUnconvergedResidual(outcome.contactResidual_N, reaction.norm());
  outcome.contactIterations = m_inUse->iterations();
  outcome.candidates = static_cast<int>(m_inUse->candidates().size());
  outcome.isUpdateRefused = m_isRefusing;
  outcome.isPassedThrough = m_isPassedThrough;
  m_isPassedThrough = false;  // reported once, at the step that takes the update in
  // A step that does not settle (the probe gone past what the body linearised at the last update
  // can answer) is rolled back: the body and the probe's force stay at the last settled step's.
  if (outcome.isSettled) {
    m_settledForces = m_inUse->nodeForces();
    m_settledOwner = m_inUse;
    m_inUse->firstBodyPositions(m_settledForces, corners_m);
    m_settledCorners = corners_m;
    m_settledProbeForce_N = reaction;
  } else {
    corners_m = m_settledCorners;
  }
  outcome.probeForce_N = m_settledProbeForce_N;
  if (!m_isInFlight && !wouldRepeatLastUpdate(tip_m, top_m)) startUpdate(tip_m, top_m);
  ++m_stepsSinceUpdate;
  return outcome;
}

bool HapticRateBody::isAtRest() const {
  if (!m_heldPoints.empty() || m_letGoSteps > 0 || m_settledProbeForce_N.squaredNorm() > 0.0)
    return false;
  return (m_settledCorners - m_startCorners).cwiseAbs().maxCoeff() <= kRestingDisplacement_m;
}

void HapticRateBody::grasp(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m) {
  m_heldPoints.clear();
  std::vector<Eigen::Vector3d> offsets;
  const std::vector<int>& ids = m_inUse->pointIds();
  for (std::size_t p = 0; p < ids.size(); ++p) {
    const Eigen::Vector3d offset_m = m_inUse->pointPosition(static_cast<Eigen::Index>(p)) - tip_m;
    if (offset_m.norm() > kGraspReachRadii * m_settings.probeRadius_m) continue;
    m_heldPoints.push_back(ids[p]);
    offsets.push_back(offset_m);
  }
  m_heldOffsets_m.resize(3, static_cast<Eigen::Index>(offsets.size()));
  for (std::size_t h = 0; h < offsets.size(); ++h)
    m_heldOffsets_m.col(static_cast<Eigen::Index>(h)) = offsets[h];
  m_closingDirection = (tip_m - top_m).normalized();
  attachHeld(*m_inUse);
}

Eigen::Matrix3d HapticRateBody::shaftTurn(const Eigen::Vector3d& tip_m,
                                          const Eigen::Vector3d& top_m) const {
  return Eigen::Quaterniond::FromTwoVectors(m_closingDirection, (tip_m - top_m).normalized())
      .toRotationMatrix();
}

void HapticRateBody::startLettingGo(const Eigen::Vector3d& tip_m, const Eigen::Vector3d& top_m) {
  // From where the held targets are now: the turned offsets from the probe.
  m_letGoTargets_m = (shaftTurn(tip_m, top_m) * m_heldOffsets_m).colwise() + tip_m;
  m_letGoSteps = 1;
  m_backSteps = 0;
}

void HapticRateBody::leadHeldBack() {
  bool isBack = true;
  for (std::size_t h = 0; h < m_inUseHeld.size(); ++h) {
    const auto at = static_cast<Eigen::Index>(h);
    auto target = m_letGoTargets_m.col(m_inUseHeld[h]);
    const Eigen::Vector3d toFree_m = m_inUse->heldFreePosition(at) - target;
    const double distance_m = toFree_m.norm();
    const double travel_m =
        std::min(m_settings.letGoTravel_m, distance_m / static_cast<double>(kLetGoApproachSteps));
    if (distance_m > kLetGoReached_m) {
      target += (travel_m / distance_m) * toFree_m;
      isBack = false;
    } else {
      target += toFree_m;
    }
    m_inUse->heldTargets().col(at) = target;
  }
  // Let go once the targets have stayed where the points settle through two updates' worth of
  // steps: each update linearises the body nearer its rest, which moves xFree on.
  m_backSteps = isBack ? m_backSteps + 1 : 0;
  const long settledSteps = std::max(kLetGoBackSteps, 2 * m_settings.latencySteps + 1);
  if (m_backSteps > settledSteps || ++m_letGoSteps > kLongestLetGoSteps) {
    m_letGoSteps = 0;
    letGo();
  }
}

void HapticRateBody::letGo() {
  m_heldPoints.clear();
  m_heldOffsets_m.resize(3, 0);
  attachHeld(*m_inUse);
}

void HapticRateBody::attachHeld(CondensedCapsuleContact& contact) {
  m_inUseHeld.clear();
  const std::vector<int>& ids = contact.pointIds();
  std::vector<Eigen::Index> local;
  for (std::size_t h = 0; h < m_heldPoints.size(); ++h) {
    const auto at = std::find(ids.begin(), ids.end(), m_heldPoints[h]);
    if (at == ids.end()) continue;  // not in this contact (made before the jaws closed)
    m_inUseHeld.push_back(static_cast<int>(h));
    local.push_back(at - ids.begin());
  }
  Eigen::Matrix3Xi nodes(3, static_cast<Eigen::Index>(local.size()));
  Eigen::Matrix3Xd weights(3, static_cast<Eigen::Index>(local.size()));
  const std::vector<CapsulePenalty::Point>& surface = m_fem->surface();
  const std::vector<int>& candidates = contact.candidates();
  for (std::size_t h = 0; h < local.size(); ++h) {
    const CapsulePenalty::Point& point =
        surface[static_cast<std::size_t>(m_heldPoints[static_cast<std::size_t>(m_inUseHeld[h])])];
    for (int a = 0; a < 3; ++a) {
      nodes(a, static_cast<Eigen::Index>(h)) =
          static_cast<int>(std::lower_bound(candidates.begin(), candidates.end(),
                                            point.nodes[static_cast<std::size_t>(a)]) -
                           candidates.begin());
    }
    weights.col(static_cast<Eigen::Index>(h)) = point.weights;
  }
  contact.setHeldPoints(nodes, weights);
  contact.heldStiffness_N_m = kHeldStiffness_N_m;
}

std::vector<int> HapticRateBody::heldCorners() const {
  std::vector<int> corners;
  const std::vector<CapsulePenalty::Point>& surface = m_fem->surface();
  for (const int p : m_heldPoints) {
    for (const int node : surface[static_cast<std::size_t>(p)].nodes) {
      if (node < m_mesh.cornerCount) corners.push_back(node);
    }
  }
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  return corners;
}

void HapticRateBody::restartSettled() {
  *m_inUse = m_start;
  m_settledOwner = m_inUse;
  m_settledForces.setZero(3, static_cast<Eigen::Index>(m_start.candidates().size()));
  m_settledCorners = m_startCorners;
  m_settledProbeForce_N.setZero();
  m_lastResidual_N = std::numeric_limits<double>::infinity();
}

void HapticRateBody::reset() {
  if (m_isInFlight) waitForUpdate();
  m_isInFlight = false;
  m_fem->restart();
  restartSettled();
  letGo();
  m_wasGrasping = false;  // jaws still closed catch the body at rest at the next step
  m_letGoSteps = 0;
  m_isRefusing = false;
  m_isPassedThrough = false;
  m_updateProblem.clear();
  m_hasJobTip = false;
}

}  // namespace tissuesim
