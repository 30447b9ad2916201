// SPDX-License-Identifier: Apache-2.0
#include "analysis/OrganPokeExperiment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

#include "analysis/SecondsSince.h"
#include "fem/FemModel.h"
#include "fem/FemStaticSolver.h"
#include "fem/HapticRateFem.h"
#include "fem/QuadraticTetMesh.h"
#include "fem/QuadraticTetWeight.h"
#include "fem/SampledSurface.h"
#include "forces/CapsulePenalty.h"
#include "forces/NodalLoads.h"
#include "forces/PlanePenalty.h"
#include "forces/SummedEnergies.h"
#include "mesh/TriangleSurface.h"

namespace tissuesim {
namespace {

/// The probe's shaft beyond the tip's hemisphere (m): longer than any organ is deep.
constexpr double kShaftLength_m = 0.3;
/// Newton iterations a solve may take to reach the next depth from the last, or the next share of
/// the weight.
constexpr int kPokeIterations = 50;
/// The first share of the body's weight put on, and the smallest increment tried.
constexpr double kFirstLoadShare = 0.25;
constexpr double kSmallestLoadShare = 1.0 / 64.0;

/// Each quadratic boundary node's share of the surface (m^2; 0 off the surface): the linear
/// boundary's faces, each cut into four at its edges' midpoints.
Eigen::VectorXd surfaceShares(const TetMesh& organ, const QuadraticTetMesh& quadratic) {
  return vertexAreas(quadratic.nodes_m, quadraticSurfacePieces(organ, quadratic));
}

/// What both FEM pokes share: the organ's quadratic mesh, the entry point, the held DOFs and the
/// surface nodes near the entry that the probe may touch.
struct PokeBody {
  PokeBody(const TetMesh& organ, const OrganPokeSetup& setup)
      : direction(setup.direction.normalized()),
        mesh(makeQuadraticTetMesh(organ)),
        shares(surfaceShares(organ, mesh)) {
    if (!firstCrossing(organ.nodes_m, boundaryFaces(organ), setup.tipStart_m, direction, entry))
      throw std::invalid_argument("the probe's axis does not meet the organ's surface");
    restEntry = entry;
    isFixed.assign(static_cast<std::size_t>(3 * mesh.nodeCount()), 0);
    int fixedCount = 0;
    for (Eigen::Index i = 0; i < mesh.nodeCount(); ++i) {
      if (setup.fixedBox_m.contains(mesh.nodes_m.col(i))) {
        std::fill_n(isFixed.begin() + 3 * i, 3, char{1});
        ++fixedCount;
      }
    }
    if (fixedCount == 0) throw std::invalid_argument("no node of the organ lies in the fixed box");
    choosePoints(organ, setup, entry);
  }

  /// The probe's points: the surface's near `centre_m` at rest.
  void choosePoints(const TetMesh& organ, const OrganPokeSetup& setup,
                    const Eigen::Vector3d& centre_m) {
    points.clear();
    if (setup.contactSpacing_m > 0.0) {
      points =
          sampleSurfacePoints(mesh, quadraticSurfacePieces(organ, mesh), setup.contactSpacing_m,
                              setup.pressureStiffness_Pa_m, centre_m, setup.contactReach_m);
      return;
    }
    for (int node = 0; node < static_cast<int>(shares.size()); ++node) {
      if (!(shares[node] > 0.0) ||
          (mesh.nodes_m.col(node) - centre_m).norm() > setup.contactReach_m)
        continue;
      points.push_back(
          {{node, node, node}, {1.0, 0.0, 0.0}, shares[node] * setup.pressureStiffness_Pa_m});
    }
  }

  /// The entry point where the probe's axis meets the body's surface at x (3 by #V, settled),
  /// and the probe's points chosen again around where the surface there was at rest: the surface
  /// node nearest that entry.
  void settleAt(const TetMesh& organ, const OrganPokeSetup& setup, const Eigen::Matrix3Xd& x) {
    const Eigen::Matrix3Xd corners = x.leftCols(organ.nodes_m.cols());
    if (!firstCrossing(corners, boundaryFaces(organ), setup.tipStart_m, direction, entry))
      throw std::invalid_argument("the probe's axis does not meet the organ's settled surface");
    Eigen::Index nearest = -1;
    double nearestDistance_m = std::numeric_limits<double>::infinity();
    for (Eigen::Index node = 0; node < shares.size(); ++node) {
      const double distance_m = (x.col(node) - entry).norm();
      if (shares[node] > 0.0 && distance_m < nearestDistance_m) {
        nearest = node;
        nearestDistance_m = distance_m;
      }
    }
    choosePoints(organ, setup, mesh.nodes_m.col(nearest));
  }
  /// The probe's tip (its hemisphere's centre) with its end `depth_m` past the entry point.
  Eigen::Vector3d tip(double depth_m, double radius_m) const {
    return entry + (depth_m - radius_m) * direction;
  }
  Eigen::Vector3d top(const Eigen::Vector3d& tip_m) const {
    return tip_m - kShaftLength_m * direction;
  }

  Eigen::Vector3d direction;
  Eigen::Vector3d entry;      ///< on the surface the probe comes down on (settled)
  Eigen::Vector3d restEntry;  ///< on the surface at rest
  QuadraticTetMesh mesh;
  Eigen::VectorXd shares;  ///< surfaceShares'
  std::vector<char> isFixed;
  std::vector<CapsulePenalty::Point> points;
};

/// The body brought to balance under its weight (with the model's other extra energies) from x:
/// the weight put on in increments, each Newton-converged (a liver's lobe sags centimetres, too
/// far for one Newton solve from rest), an increment that does not converge tried again in
/// halves. The caller sets the model's definite tangent for it: the exact one is indefinite over
/// much of a hanging liver's path, and shifted into definiteness took several times the
/// iterations to the same balance. The iterations into curve's counts. @returns the weight's size
/// (N). @throws std::invalid_argument where an increment of kSmallestLoadShare does not converge.
double settleUnderWeight(const FemModel& model, const std::vector<char>& isFixed,
                         NodalLoads& weight, FemStaticSolver& solver, Eigen::Matrix3Xd& x,
                         IndentationCurve& curve) {
  const Eigen::Matrix3Xd fullLoads_N = weight.forces_N;
  const double weight_N = fullLoads_N.rowwise().sum().norm();
  double share = 0.0, increment = kFirstLoadShare;
  Eigen::Matrix3Xd lastBalance = x;
  while (share < 1.0) {
    const double next = std::min(1.0, share + increment);
    weight.forces_N = next * fullLoads_N;
    solver.setTolerance(1e-9 * std::max(1.0, next * weight_N));
    const auto solveStart = std::chrono::steady_clock::now();
    const FemSolveReport report = solver.solve(model, x, isFixed);
    curve.solving_s += secondsSince(solveStart);
    curve.newtonIterations += report.iterations;
    curve.settlingIterations += report.iterations;
    if (report.converged) {
      share = next;
      lastBalance = x;
      continue;
    }
    x = lastBalance;
    increment /= 2.0;
    if (increment < kSmallestLoadShare) {
      weight.forces_N = fullLoads_N;
      throw std::invalid_argument("the organ does not come to balance under its weight (" +
                                  std::to_string(report.residual_N) + " N left on a node at " +
                                  std::to_string(static_cast<int>(std::lround(100.0 * next))) +
                                  " % of it)");
    }
  }
  return weight_N;
}

void checkDepths(const std::vector<double>& depths_m) {
  for (std::size_t d = 0; d < depths_m.size(); ++d) {
    if (!(depths_m[d] > (d > 0 ? depths_m[d - 1] : 0.0)))
      throw std::invalid_argument("poke depths must increase, each above 0");
  }
}

}  // namespace

IndentationCurve pokeOrganFem(const StrainEnergy& energy, const TetMesh& organ,
                              const OrganPokeSetup& setup, double bulkModulus_Pa,
                              const std::function<void(double, double)>& onDepth) {
  const auto start = std::chrono::steady_clock::now();
  checkDepths(setup.depths_m);
  PokeBody body(organ, setup);
  FemModel model(body.mesh, energy, bulkModulus_Pa);
  IndentationCurve curve;
  curve.nodes = static_cast<int>(body.mesh.nodeCount());
  curve.elements = static_cast<int>(body.mesh.tetCount());
  FemStaticSolver solver(1e-9, kPokeIterations);
  Eigen::Matrix3Xd x = body.mesh.nodes_m;

  // Under gravity: the body balanced under its weight and the tray, the probe clear.
  double weight_N = 0.0;
  NodalLoads weight;
  std::unique_ptr<PlanePenalty> tray;
  SummedEnergies support;
  if (setup.gravity_m_s2.squaredNorm() > 0.0) {
    weight = quadraticTetWeight(body.mesh, setup.density_kg_m3, setup.gravity_m_s2);
    support.terms.push_back(&weight);
    if (setup.tray) {
      if (!(setup.tray->stiffness_Pa_per_m > 0.0))
        throw std::invalid_argument("the tray's stiffness must be > 0");
      std::vector<CapsulePenalty::Point> trayPoints;
      for (int node = 0; node < static_cast<int>(body.shares.size()); ++node) {
        if (body.shares[node] > 0.0)
          trayPoints.push_back({{node, node, node},
                                {1.0, 0.0, 0.0},
                                body.shares[node] * setup.tray->stiffness_Pa_per_m});
      }
      tray = std::make_unique<PlanePenalty>(std::move(trayPoints), setup.tray->up,
                                            setup.tray->height_m);
      support.terms.push_back(tray.get());
    }
    model.setExtraEnergy(&support);
    model.setTangent(FemTangent::Definite);
    weight_N = settleUnderWeight(model, body.isFixed, weight, solver, x, curve);
    model.setTangent(FemTangent::Exact);
    body.settleAt(organ, setup, x);
    curve.entrySag_m = (body.entry - body.restEntry).norm();
  } else if (setup.tray) {
    throw std::invalid_argument("a tray needs gravity to hold the organ on it");
  }
  CapsulePenalty probe(body.points);
  probe.radius_m = setup.probeRadius_m;
  support.terms.push_back(&probe);
  model.setExtraEnergy(&support);
  const auto force = [&] { return probe.reaction(x).dot(-body.direction); };
  double depth = 0.0;
  double lastForce_N = 0.0;
  for (const double target : setup.depths_m) {
    const int steps = static_cast<int>(std::ceil((target - depth) / setup.depthStep_m - 1e-9));
    const double from = depth;
    for (int s = 1; s <= steps; ++s) {
      depth = from + (target - from) * s / steps;
      probe.tip_m = body.tip(depth, setup.probeRadius_m);
      probe.top_m = body.top(probe.tip_m);
      // Relative to the force at the last equilibrium (round-off grows with it), not at the
      // start of this solve, where the probe has just moved into the surface.
      solver.setTolerance(1e-9 * std::max({1.0, std::abs(lastForce_N), weight_N}));
      const auto solveStart = std::chrono::steady_clock::now();
      const FemSolveReport report = solver.solve(model, x, body.isFixed);
      curve.solving_s += secondsSince(solveStart);
      curve.newtonIterations += report.iterations;
      curve.worstResidual_N = std::max(curve.worstResidual_N, report.residual_N);
      if (!report.converged) ++curve.unconvergedPoints;
      lastForce_N = force();
    }
    curve.force_N.push_back(lastForce_N);
    if (onDepth) onDepth(target, lastForce_N);
  }
  curve.seconds = secondsSince(start);
  return curve;
}

HapticRatePoke pokeOrganHapticRate(const StrainEnergy& energy, const TetMesh& organ,
                                   const OrganPokeSetup& setup, double bulkModulus_Pa,
                                   const HapticRateSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  checkDepths(setup.depths_m);
  if (!(settings.speed_m_s > 0.0) || !(settings.hapticStep_s > 0.0) ||
      !(settings.updateLatency_s >= 0.0) || !(settings.startAbove_m >= 0.0))
    throw std::invalid_argument(
        "the haptic-rate poke's speed and step must be > 0, its latency and start >= 0");
  if (setup.gravity_m_s2.squaredNorm() > 0.0 || setup.tray)
    throw std::invalid_argument("the haptic-rate poke runs weightless, on no tray");
  const PokeBody body(organ, setup);
  FemModel model(body.mesh, energy, bulkModulus_Pa);
  HapticRateFem fem(model, body.isFixed, body.points, settings.candidateMargin_m,
                    settings.newtonIterations);
  fem.setStiffeningBetweenUpdates(settings.isStiffeningBetweenUpdates);

  HapticRatePoke poke;
  poke.nodes = static_cast<int>(body.mesh.nodeCount());
  poke.elements = static_cast<int>(body.mesh.tetCount());
  const double radius_m = setup.probeRadius_m;
  const auto depthAt = [&](long step) {
    return -settings.startAbove_m + settings.speed_m_s * settings.hapticStep_s * step;
  };
  const double deepest_m = setup.depths_m.back();
  const long steps = static_cast<long>(std::ceil((deepest_m + settings.startAbove_m) /
                                                 (settings.speed_m_s * settings.hapticStep_s)));
  poke.stepTimes_ms.reserve(static_cast<std::size_t>(steps) + 1);

  // The body at rest linearised before the clock starts (the start-up), then an update in
  // flight from the first step on.
  CondensedCapsuleContact inUse, next;
  const auto update = [&](long step) {
    const Eigen::Vector3d tip = body.tip(depthAt(step), radius_m);
    const auto updateStart = std::chrono::steady_clock::now();
    const HapticRateUpdate report = fem.update(inUse, tip, body.top(tip), radius_m, next);
    const double wall_s = secondsSince(updateStart);
    if (!report.isStepped) ++poke.unsteppedUpdates;
    poke.maxCandidates = std::max(poke.maxCandidates, report.candidates);
    return wall_s;
  };
  update(0);
  std::swap(inUse, next);
  double readyAt_s = -1.0;  // no update in flight yet
  std::size_t nextDepth = 0;
  double lastDepth_m = depthAt(0), lastForce_N = 0.0;
  for (long step = 0; step <= steps + 1 && nextDepth < setup.depths_m.size(); ++step) {
    const double time_s = settings.hapticStep_s * step;
    const bool isReady = time_s >= readyAt_s - 1e-3 * settings.hapticStep_s;  // round-off
    if (isReady && readyAt_s >= 0.0) {
      next.startFrom(inUse);
      std::swap(inUse, next);
    }
    const double depth_m = depthAt(step);
    const Eigen::Vector3d tip = body.tip(depth_m, radius_m);
    const auto stepStart = std::chrono::steady_clock::now();
    const Eigen::Vector3d reaction = inUse.solve(tip, body.top(tip), radius_m);
    poke.stepTimes_ms.push_back(1e3 * secondsSince(stepStart));
    if (!inUse.converged()) ++poke.unconvergedSteps;
    ++poke.steps;
    const double force_N = reaction.dot(-body.direction);
    while (nextDepth < setup.depths_m.size() && depth_m >= setup.depths_m[nextDepth]) {
      const double target = setup.depths_m[nextDepth++];
      const double share = (target - lastDepth_m) / (depth_m - lastDepth_m);
      poke.force_N.push_back(lastForce_N + share * (force_N - lastForce_N));
    }
    lastDepth_m = depth_m;
    lastForce_N = force_N;
    if (isReady) {  // the FEM takes the contact's forces now and answers after its latency
      const double wall_s = update(step);
      ++poke.updates;
      poke.updating_s += wall_s;
      poke.longestUpdate_s = std::max(poke.longestUpdate_s, wall_s);
      const double latency_s = settings.updateLatency_s > 0.0 ? settings.updateLatency_s : wall_s;
      readyAt_s = time_s + std::max(settings.hapticStep_s, latency_s);
    }
  }
  if (poke.force_N.size() != setup.depths_m.size())
    throw std::logic_error("the haptic-rate poke stopped short of its deepest depth");
  poke.seconds = secondsSince(start);
  return poke;
}

}  // namespace tissuesim
