// SPDX-License-Identifier: Apache-2.0
#include "app/trade/TradeGrid.h"

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <optional>

#include <nlohmann/json.hpp>

#include "analysis/GoodnessOfFit.h"
#include "analysis/IndentationHapticRate.h"
#include "analysis/NetworkCalibration.h"
#include "analysis/TensileExperiment.h"
#include "app/CommandError.h"
#include "app/FemForceCache.h"
#include "app/LoadedTissue.h"
#include "app/OrganPoke.h"
#include "app/Percentile.h"
#include "app/ProcessMemory.h"
#include "app/SceneSession.h"
#include "collision/CapsuleContact.h"
#include "fem/FemModel.h"
#include "mesh/IsolatedCall.h"
#include "mesh/LatticeMesher.h"
#include "mesh/SurfaceEmbedding.h"
#include "sim/SceneGeometry.h"
#include "sim/Simulation.h"

namespace tissuesim::app {
namespace {

using Clock = std::chrono::steady_clock;

double secondsBetween(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

/// The share of the deepest force a quadratic row's solves may leave on a node.
constexpr double kQuadraticKeptShare = 1e-5;

/// The haptic-rate row's contact points this far apart (m): organ-poke's default.
constexpr double kHapticRateSpacing_m = 0.001;

/// The bundled scene with the row's knobs.
SceneDescription sceneOf(const SceneDescription& bundled, const TradeRow& row) {
  SceneDescription scene = bundled;
  scene.tetMesh.reset();
  scene.targetSprings = row.targetSprings;
  scene.springLaw = row.law;
  scene.bulkModulus_Pa = row.bulkModulus_Pa;
  scene.integrator = row.integrator;
  scene.newtonIterations = row.newtonIterations;
  scene.linearTolerance = row.cgTolerance;
  scene.threads = row.threads;
  scene.model = row.model;
  if (row.model == "fem") scene.isSoftening = false;
  if (row.isOnOrganMesh()) {
    // The FEM as on the organ's conformal meshes: contact on the mesh's own boundary, which is
    // the drawn surface remeshed.
    scene.surface.reset();
    scene.tetMesh = SceneMeshSource{row.organMeshPath, 1.0, "", std::nullopt};
    scene.targetSprings = 0;
    scene.volumeCells = "nodes";
    scene.strainCells = row.strainCells;
  }
  return scene;
}

/// The default poke through the scene, timed; its figures as JSON text (the child's reply).
std::string timeLiverPoke(const SceneDescription& scene, double duration_s) {
  // The child shares its parent's pages, its freed heap among them (which it would reuse
  // without a page more), and inherits its high-water mark: the free heap is handed back and the
  // mark reset to what the child holds now, so the peak above it is this scene's alone.
  malloc_trim(0);
  resetPeakResident();
  const double baseline_MB = residentBytes() / 1e6;
  const auto start = Clock::now();
  SceneSession session(scene, "", InstrumentDriver::Script);
  Simulation& simulation = session.simulation();
  const double startup_s = secondsBetween(start, Clock::now());
  const double simulated_s = duration_s > 0.0 ? duration_s : session.script()->duration_s();
  const long steps = std::lround(simulated_s / simulation.timeStep_s());
  std::vector<double> stepTimes_ms;
  stepTimes_ms.reserve(static_cast<std::size_t>(steps));
  const auto loop = Clock::now();
  for (long n = 0; n < steps; ++n) {
    const auto before = Clock::now();
    simulation.step();
    stepTimes_ms.push_back(1e3 * secondsBetween(before, Clock::now()));
  }
  const double wall_s = secondsBetween(loop, Clock::now());
  nlohmann::json reply;
  reply["springs"] = simulation.springMesh().springCount();
  reply["nodes"] = simulation.springMesh().nodeCount();
  reply["startup_s"] = startup_s;
  reply["median_ms"] = percentile(stepTimes_ms, 0.5);
  reply["p99_ms"] = percentile(stepTimes_ms, 0.99);
  reply["steps_per_s"] = wall_s > 0.0 ? static_cast<double>(steps) / wall_s : 0.0;
  reply["memory_mb"] = std::max(0.0, peakResidentBytes() / 1e6 - baseline_MB);
  reply["events"] = simulation.eventCount();
  return reply.dump();
}

/// The simulator's contact on a block: the instrument against a drawn top face (a grid of the
/// liver's drawn-surface spacing) embedded in the block's tet mesh, as on the liver
/// (collision/CapsuleContact.h). Owns the drawn face and its embedding.
class DrawnTopContact final : public ContactProvider {
 public:
  DrawnTopContact(const TetMesh& block, const Eigen::Vector3d& size_m, double spacing_m,
                  const CapsuleContactSettings& settings) {
    const int cellsX = std::max(1, static_cast<int>(std::lround(size_m.x() / spacing_m)));
    const int cellsY = std::max(1, static_cast<int>(std::lround(size_m.y() / spacing_m)));
    m_surface.vertices_m.resize(3, (cellsX + 1) * (cellsY + 1));
    m_surface.triangles.resize(3, 2 * cellsX * cellsY);
    const auto vertex = [&](int i, int j) { return j * (cellsX + 1) + i; };
    for (int j = 0; j <= cellsY; ++j) {
      for (int i = 0; i <= cellsX; ++i) {
        m_surface.vertices_m.col(vertex(i, j)) =
            Eigen::Vector3d(size_m.x() * i / cellsX, size_m.y() * j / cellsY, size_m.z());
      }
    }
    Eigen::Index t = 0;
    for (int j = 0; j < cellsY; ++j) {
      for (int i = 0; i < cellsX; ++i) {
        m_surface.triangles.col(t++) << vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1);
        m_surface.triangles.col(t++) << vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1);
      }
    }
    m_embedding.emplace(block, m_surface.vertices_m);
    m_contact.emplace(block, m_surface, *m_embedding, settings);
  }

  void findContacts(const Eigen::Matrix3Xd& x, const InstrumentPose& pose,
                    PenaltyContactSet& contacts) override {
    m_contact->findContacts(x, pose, contacts);
  }

 private:
  TriangleSurface m_surface;
  std::optional<SurfaceEmbedding> m_embedding;
  std::optional<CapsuleContact> m_contact;
};

/// The mean edge length of a surface's triangles (m).
double meanEdge(const TriangleSurface& surface) {
  double sum = 0.0;
  for (Eigen::Index t = 0; t < surface.triangleCount(); ++t) {
    for (int e = 0; e < 3; ++e) {
      sum += (surface.vertices_m.col(surface.triangles(e, t)) -
              surface.vertices_m.col(surface.triangles((e + 1) % 3, t)))
                 .norm();
    }
  }
  return sum / std::max<double>(1.0, 3.0 * static_cast<double>(surface.triangleCount()));
}

}  // namespace

std::vector<TradeRow> tradeRows(const SceneDescription& bundled, const TradeSettings& settings) {
  TradeRow base;
  base.law = bundled.springLaw;
  base.bulkModulus_Pa = bundled.bulkModulus_Pa;
  base.integrator = bundled.integrator;
  base.newtonIterations = bundled.newtonIterations;
  base.cgTolerance = bundled.linearTolerance;
  base.threads = std::max(1, bundled.threads);
  const auto springsName = [](int springs) { return "springs ~" + std::to_string(springs); };
  std::vector<TradeRow> rows;
  for (const int springs : settings.resolutions) {
    TradeRow row = base;
    row.knob = "resolution";
    row.targetSprings = springs;
    row.name = springsName(springs) + " (bundled settings)";
    rows.push_back(row);
  }
  if (base.threads > 1) {
    for (const int springs : settings.resolutions) {
      TradeRow row = base;
      row.knob = "threads";
      row.targetSprings = springs;
      row.threads = 1;
      row.name = springsName(springs) + ", 1 thread";
      rows.push_back(row);
    }
  }
  // The other knobs at the resolution nearest the bundled mesh's.
  const int home = *std::min_element(
      settings.resolutions.begin(), settings.resolutions.end(),
      [](int a, int b) { return std::abs(std::log(a / 5300.0)) < std::abs(std::log(b / 5300.0)); });
  base.targetSprings = home;
  const std::string at = ", " + springsName(home);
  for (const char* law : {"eesm", "eesm-paper", "smm"}) {
    if (law == base.law) continue;
    TradeRow row = base;
    row.knob = "model";
    row.law = law;
    row.name = std::string("law ") + law + at;
    rows.push_back(row);
  }
  {
    TradeRow row = base;
    row.knob = "volume";
    row.bulkModulus_Pa = base.bulkModulus_Pa > 0.0 ? 0.0 : 100e3;
    row.name = (base.bulkModulus_Pa > 0.0 ? std::string("no volume term")
                                          : std::string("volume term 100 kPa")) +
               at;
    rows.push_back(row);
  }
  struct Newton {
    int iterations;
    double tolerance;
  };
  for (const Newton newton : {Newton{2, 1e-6}, Newton{8, 1e-8}}) {
    TradeRow row = base;
    row.knob = "integrator";
    row.integrator = "implicit";
    row.newtonIterations = newton.iterations;
    row.cgTolerance = newton.tolerance;
    char name[96];
    std::snprintf(name, sizeof name, "implicit, Newton %d, CG %.0e%s", newton.iterations,
                  newton.tolerance, at.c_str());
    row.name = name;
    rows.push_back(row);
  }
  {
    TradeRow row = base;
    row.knob = "integrator";
    row.integrator = "explicit";
    row.name = "explicit" + at;
    rows.push_back(row);
  }
  {
    TradeRow row = base;
    row.knob = "integrator";
    row.integrator = "quasi-newton";
    row.newtonIterations = std::max(base.newtonIterations, 2);
    row.name = "quasi-newton, " + std::to_string(row.newtonIterations) + " iterations" + at;
    rows.push_back(row);
  }
  for (const int springs : settings.tetResolutions) {
    TradeRow row = base;
    row.knob = "fem-tets";
    row.model = "fem";
    row.targetSprings = springs;
    row.bulkModulus_Pa = settings.tetBulkModulus_Pa;
    row.name = "fem on the lattice, tets of " + springsName(springs);
    rows.push_back(row);
  }
  for (const char* cells : {"tets", "faces"}) {
    for (const OrganMesh& mesh : settings.organMeshes) {
      TradeRow row = base;
      row.knob = "fem-organ";
      row.model = "fem";
      row.bulkModulus_Pa = settings.organMeshBulkModulus_Pa;
      row.organMeshPath = mesh.path;
      row.organMeshLabel = mesh.label;
      row.strainCells = cells;
      row.name = std::string("fem per ") + (cells == std::string("tets") ? "tet" : "face") +
                 " on the organ's mesh " + mesh.label;
      rows.push_back(row);
    }
  }
  // The reference's element on an organ's mesh, static or at its own rate.
  const auto quadraticRow = [&](const OrganMesh& mesh, const char* knob, const char* element,
                                const std::string& name) {
    TradeRow row = base;
    row.knob = knob;
    row.model = "fem";
    row.element = element;
    row.strainCells.clear();
    row.integrator = row.isHapticRate() ? "haptic-rate" : "static";
    row.threads = 1;
    row.bulkModulus_Pa = settings.tetBulkModulus_Pa;
    row.organMeshPath = mesh.path;
    row.organMeshLabel = mesh.label;
    row.name = name + mesh.label;
    return row;
  };
  for (const OrganMesh& mesh : settings.organMeshes) {
    rows.push_back(quadraticRow(mesh, "fem-quadratic", "quadratic",
                                "fem quadratic tets, static, on the organ's mesh "));
  }
  if (settings.hapticRateScene) {
    const SceneDescription& scene = *settings.hapticRateScene;
    if (scene.model != "fem-haptic-rate" || !scene.tetMesh)
      throw CommandError(scene.source.string() +
                         ": the haptic-rate row's scene runs effects.model fem-haptic-rate on a "
                         "tet mesh");
    const std::string stem = scene.source.stem().string();
    TradeRow row = quadraticRow(OrganMesh{scene.tetMesh->file.string(), stem}, "fem-haptic-rate",
                                "haptic-rate",
                                "fem quadratic tets at their own rate, the contact at 1 kHz: "
                                "the scene ");
    row.bulkModulus_Pa = scene.bulkModulus_Pa;
    row.newtonIterations = scene.newtonIterations;
    rows.push_back(row);
  }
  for (const int refinement : settings.femRows) {
    TradeRow row;
    row.knob = "reference";
    row.femRefinement = refinement;
    row.name = "fem, refinement " + std::to_string(refinement);
    rows.push_back(row);
  }
  return rows;
}

TradeCost measureLiverCost(const SceneDescription& bundled, const TradeRow& row,
                           double duration_s) {
  const SceneDescription scene = sceneOf(bundled, row);
  IsolationLimits limits;
  limits.wallTime = std::chrono::seconds(1200);
  limits.cpuSeconds = 2400;
  limits.addressSpaceBytes = 16ull << 30;
  const IsolatedResult result =
      runIsolated([&] { return timeLiverPoke(scene, duration_s); }, limits);
  TradeCost cost;
  if (!result.isOk) {
    cost.failure = "liver run: " + result.error;
    return cost;
  }
  const nlohmann::json reply = nlohmann::json::parse(result.bytes);
  cost.springs = reply["springs"].get<int>();
  cost.nodes = reply["nodes"].get<int>();
  cost.startup_s = reply["startup_s"].get<double>();
  cost.stepMedian_ms = reply["median_ms"].get<double>();
  cost.stepP99_ms = reply["p99_ms"].get<double>();
  cost.stepsPerSecond = reply["steps_per_s"].get<double>();
  cost.peakMemory_MB = reply["memory_mb"].get<double>();
  cost.events = reply["events"].get<long>();
  return cost;
}

TradeCost medianOfRounds(const std::vector<TradeCost>& rounds) {
  TradeCost combined = rounds.front();
  const auto median = [&](double TradeCost::*field) {
    std::vector<double> values;
    for (const TradeCost& round : rounds) values.push_back(round.*field);
    return percentile(values, 0.5);
  };
  combined.startup_s = median(&TradeCost::startup_s);
  combined.stepMedian_ms = median(&TradeCost::stepMedian_ms);
  combined.stepP99_ms = median(&TradeCost::stepP99_ms);
  combined.stepsPerSecond = median(&TradeCost::stepsPerSecond);
  for (const TradeCost& round : rounds) {
    combined.peakMemory_MB = std::max(combined.peakMemory_MB, round.peakMemory_MB);
    combined.events = std::max(combined.events, round.events);
    if (combined.failure.empty()) combined.failure = round.failure;
  }
  return combined;
}

void setSurfaceGap(const std::vector<Eigen::Vector3d>& model_m,
                   const std::vector<Eigen::Vector3d>& reference_m, TradeMeasurement& out) {
  double sum = 0.0;
  double worst = 0.0;
  const std::size_t count = std::min(model_m.size(), reference_m.size());
  for (std::size_t i = 0; i < count; ++i) {
    const double gap = (model_m[i] - reference_m[i]).norm();
    sum += gap * gap;
    worst = std::max(worst, gap);
  }
  out.surfaceRms_mm = count > 0 ? 1e3 * std::sqrt(sum / static_cast<double>(count)) : 0.0;
  out.surfaceMax_mm = 1e3 * worst;
}

IndentationCurve measureReference(const LoadedTissue& tissue, const TradeSettings& settings,
                                  int refinement) {
  IndentationSetup setup;
  setup.depths_m = settings.depths_m;
  return indentFem(tissue.energy, setup, refinement, defaultFemBulkModulus(tissue.energy));
}

TradeErrors::TradeErrors(const LoadedTissue& tissue, const SceneDescription& bundled,
                         const TradeSettings& settings)
    : m_tissue(tissue), m_bundled(bundled), m_settings(settings) {
  SceneGeometry geometry;
  try {
    geometry = loadSceneGeometry(bundled);
  } catch (const SceneFileError& error) {
    throw CommandError(error.what());
  }
  if (!geometry.surface || !bundled.instrument) {
    throw CommandError(bundled.source.string() +
                       ": trade needs a scene with a drawn surface (meshed at each resolution) "
                       "and an instrument (the poke)");
  }
  m_surface = std::move(*geometry.surface);
}

double TradeErrors::stiffnessScale(double bulkModulus_Pa) {
  auto found = m_stiffnessScales.find(bulkModulus_Pa);
  if (found == m_stiffnessScales.end()) {
    found = m_stiffnessScales
                .emplace(bulkModulus_Pa,
                         simulatorStiffnessScale(m_tissue.energy, m_tissue.table, bulkModulus_Pa))
                .first;
  }
  return found->second;
}

double TradeErrors::cellEdge(int springs) const {
  return edgeLengthForSpringCount(m_surface, springs);
}

void TradeErrors::measure(const TradeRow& row, const IndentationCurve& reference,
                          TradeMeasurement& out) {
  const SpringLaw law = springLawNamed(row.law).value_or(SpringLaw::Eesm);
  const bool isTets = row.model == "fem";
  IndentationNetwork network{cellEdge(row.targetSprings), law, row.bulkModulus_Pa,
                             isTets ? 0.0 : stiffnessScale(row.bulkModulus_Pa)};
  if (isTets) network.model = LatticeModel::IsochoricTets;
  IndentationSetup setup;
  setup.depths_m = m_settings.depths_m;
  char key[160];
  std::snprintf(key, sizeof key, "%s|%d|%s|%.6g", row.model.c_str(), row.targetSprings,
                row.law.c_str(), row.bulkModulus_Pa);
  auto statics = m_static.find(key);
  if (statics == m_static.end()) {
    statics =
        m_static.emplace(key, indentSprings(m_tissue.energy, m_tissue.table, setup, network)).first;
  }
  const SceneDescription scene = sceneOf(m_bundled, row);
  IndentationPace pace;
  pace.integrator = row.integrator;
  pace.settings = realTimeIntegratorSettings(scene);
  pace.speed_m_s = kDefaultPokeDepth_m / kDefaultPokePressTime_s;
  pace.timeStep_s = scene.timeStep_s;
  char paceKey[192];
  std::snprintf(paceKey, sizeof paceKey, "%s|%s|%d|%.3g", key, row.integrator.c_str(),
                row.newtonIterations, row.cgTolerance);
  auto paced = m_pace.find(paceKey);
  if (paced == m_pace.end()) {
    const CapsuleContactSettings contact{m_bundled.instrument->shaftRadius_m,
                                         m_bundled.instrument->shaftLength_m};
    const double spacing = meanEdge(m_surface);
    const Eigen::Vector3d size = setup.size_m;
    const IndentationContactFactory makeContact =
        [&](const TetMesh& block) -> std::unique_ptr<ContactProvider> {
      return std::make_unique<DrawnTopContact>(block, size, spacing, contact);
    };
    paced = m_pace
                .emplace(paceKey, indentSpringsAtPace(m_tissue.energy, m_tissue.table, setup,
                                                      network, pace, makeContact))
                .first;
  }
  out.staticForce_N = statics->second.force_N;
  out.paceForce_N = paced->second.force_N;
  out.failedSteps = paced->second.failedSteps;
  setSurfaceGap(statics->second.surfaceDisplacement_m, reference.surfaceDisplacement_m, out);

  char tensileKey[96];
  std::snprintf(tensileKey, sizeof tensileKey, "%s|%.6g", isTets ? "tets" : row.law.c_str(),
                row.bulkModulus_Pa);
  auto tensile = m_tensile.find(tensileKey);
  if (tensile == m_tensile.end()) {
    const UniaxialProtocol protocol{{1.15, 1.23, 1.30}, m_settings.tensilePoints};
    const std::vector<CurveBranch> sedf = m_tissue.continuum.run(UniaxialModel::Sedf, protocol);
    TensileSpecimen specimen;
    specimen.cellsAcrossThickness = m_settings.tensileResolution;
    const TensileExperiment test(m_tissue.energy, m_tissue.table, specimen);
    TensileOptions options;
    options.bulkModulus_Pa = row.bulkModulus_Pa;
    if (isTets) {
      options.model = LatticeModel::IsochoricTets;
    } else {
      options.law = law;
      options.linearModulus_Pa =
          UniaxialExperiment::springLawLinearModulus(law, m_tissue.energy, m_tissue.table);
      options.volumeScale = stiffnessScale(row.bulkModulus_Pa);
    }
    const std::vector<CurveBranch> curve = test.run(options, protocol);
    double loading = 1.0;
    double unloading = 1.0;
    for (std::size_t b = 0; b < curve.size(); ++b) {
      // The tets have no softening: their loading against the virgin curve (as `tensile
      // --model tets` reports it), and no unloading figure.
      std::vector<double> expected = sedf[b].stress_Pa;
      if (isTets) {
        if (curve[b].phase != LoadPhase::Loading) continue;
        for (std::size_t i = 0; i < expected.size(); ++i)
          expected[i] = m_tissue.energy.stress(curve[b].stretch[i]);
      }
      const double r2 = coefficientOfDetermination(expected, curve[b].stress_Pa);
      (curve[b].phase == LoadPhase::Loading ? loading : unloading) =
          std::min(curve[b].phase == LoadPhase::Loading ? loading : unloading, r2);
    }
    tensile = m_tensile.emplace(tensileKey, std::make_pair(loading, unloading)).first;
  }
  out.tensileLoadingR2 = tensile->second.first;
  out.tensileUnloadingR2 = tensile->second.second;
}

void TradeErrors::measureQuadraticOrgan(const TradeRow& row, TradeMeasurement& out) {
  const SceneDescription scene = weightlessPokeScene(m_bundled);
  const double bulkModulus_Pa = row.bulkModulus_Pa;  // the reference's (tradeRows)
  const OrganPokeSetup setup = organPokeSetup(scene, m_settings.organDepths_m);
  std::vector<double> depths_mm;
  for (const double depth_m : m_settings.organDepths_m) depths_mm.push_back(1e3 * depth_m);
  const std::uint64_t key = femReferenceKey(scene, row.organMeshPath, setup, bulkModulus_Pa);
  const std::filesystem::path meshPath(row.organMeshPath);
  const std::string cacheName = meshPath.stem().string() + "-poke.csv";
  std::vector<std::string> caches{(meshPath.parent_path() / cacheName).string()};
  if (!m_settings.organCacheFolder.empty())
    caches.push_back((std::filesystem::path(m_settings.organCacheFolder) / cacheName).string());
  std::optional<std::vector<double>> kept;
  for (const std::string& path : caches) {
    std::string why;
    kept = readFemForceCache(path, key, depths_mm, why);
    if (kept) break;
  }
  const TetMesh organ = readOrganMesh(row.organMeshPath);
  IndentationCurve curve;
  try {
    if (kept) {
      // The forces are kept; the cost is the same Newton iterations', timed to the first depth.
      OrganPokeSetup first = setup;
      first.depths_m = {setup.depths_m.front()};
      curve = pokeOrganFem(m_tissue.energy, organ, first, bulkModulus_Pa);
      curve.force_N = *kept;
    } else {
      curve = pokeOrganFem(m_tissue.energy, organ, setup, bulkModulus_Pa);
      // A solve that stops short of the solver's own tolerance (a billionth of the force) with
      // no more than a hundred-thousandth of the deepest force left on a node moves the map's
      // errors, read to half a point, by nothing: those forces are kept, and are no event.
      if (curve.worstResidual_N <= kQuadraticKeptShare * std::abs(curve.force_N.back())) {
        curve.unconvergedPoints = 0;
        if (!m_settings.organCacheFolder.empty())
          writeFemForceCache(caches.back(), key, depths_mm, curve.force_N);
      }
    }
  } catch (const std::invalid_argument& error) {
    throw CommandError(row.organMeshPath + ": " + error.what());
  }
  const double iteration_ms =
      curve.newtonIterations > 0
          ? 1e3 * curve.solving_s / static_cast<double>(curve.newtonIterations)
          : std::numeric_limits<double>::quiet_NaN();
  out.organForce_N = curve.force_N;
  out.organEvents = curve.unconvergedPoints;
  out.organStepMedian_ms = iteration_ms;
  out.organStepP99_ms = std::numeric_limits<double>::quiet_NaN();
  out.organStepsPerSecond = 1e3 / iteration_ms;
  out.cost.nodes = curve.nodes;
  out.cost.startup_s = curve.seconds - curve.solving_s;
  out.cost.stepMedian_ms = out.organStepMedian_ms;
  out.cost.stepP99_ms = out.organStepP99_ms;
  out.cost.stepsPerSecond = out.organStepsPerSecond;
  out.cost.events = out.organEvents;
}

void TradeErrors::measureHapticRateOrgan(TradeMeasurement& out) {
  const SceneDescription scene = weightlessPokeScene(*m_settings.hapticRateScene);
  const SimulatorPoke poke =
      pokeSimulator(scene, m_settings.organDepths_m, m_settings.organSpeed_m_s);
  out.organForce_N = poke.force_N;
  out.organEvents = poke.events;
  out.organStepMedian_ms = percentile(poke.stepTimes_ms, 0.5);
  out.organStepP99_ms = percentile(poke.stepTimes_ms, 0.99);
  out.organStepsPerSecond =
      poke.stepping_s > 0.0 ? static_cast<double>(poke.steps) / poke.stepping_s : 0.0;
  out.organUpdateMean_ms = poke.updateMean_ms;
  out.cost.nodes = poke.nodes;
  out.cost.startup_s = poke.seconds - poke.stepping_s;
  out.cost.stepMedian_ms = out.organStepMedian_ms;
  out.cost.stepP99_ms = out.organStepP99_ms;
  out.cost.stepsPerSecond = out.organStepsPerSecond;
  out.cost.events = out.organEvents;

  // The block through the same scheme and settings, its probe at the liver poke's speed.
  IndentationSetup setup;
  setup.depths_m = m_settings.depths_m;
  HapticRateSettings settings;
  settings.speed_m_s = m_settings.organSpeed_m_s;
  settings.newtonIterations = scene.newtonIterations;
  settings.updateLatency_s = scene.femUpdateLatency_s;
  try {
    const HapticRatePoke block =
        indentHapticRate(m_tissue.energy, setup, IndentationBodyGrading{}, scene.bulkModulus_Pa,
                         kHapticRateSpacing_m, settings);
    out.staticForce_N = block.force_N;
  } catch (const std::invalid_argument& error) {
    out.failure = std::string("block: ") + error.what();
  }
}

void TradeErrors::measureOrgan(const TradeRow& row, TradeMeasurement& out) {
  if (row.isQuadratic()) {
    measureQuadraticOrgan(row, out);
    return;
  }
  if (row.isHapticRate()) {
    measureHapticRateOrgan(out);
    return;
  }
  char key[512];
  std::snprintf(key, sizeof key, "%s|%d|%s|%.6g|%s|%d|%.3g|%s|%s", row.model.c_str(),
                row.targetSprings, row.law.c_str(), row.bulkModulus_Pa, row.integrator.c_str(),
                row.newtonIterations, row.cgTolerance, row.organMeshPath.c_str(),
                row.strainCells.c_str());
  auto poked = m_organ.find(key);
  if (poked == m_organ.end()) {
    const SimulatorPoke poke = pokeSimulator(weightlessPokeScene(sceneOf(m_bundled, row)),
                                             m_settings.organDepths_m, m_settings.organSpeed_m_s);
    TimedOrganPoke timed;
    timed.threads = row.threads;
    TradeMeasurement& measured = timed.measured;
    measured.organForce_N = poke.force_N;
    measured.organEvents = poke.events;
    measured.organStepMedian_ms = percentile(poke.stepTimes_ms, 0.5);
    measured.organStepP99_ms = percentile(poke.stepTimes_ms, 0.99);
    measured.organStepsPerSecond =
        poke.stepping_s > 0.0 ? static_cast<double>(poke.steps) / poke.stepping_s : 0.0;
    measured.cost.nodes = poke.nodes;
    measured.cost.startup_s = poke.seconds - poke.stepping_s;
    poked = m_organ.emplace(key, std::move(timed)).first;
  }
  const TradeMeasurement& measured = poked->second.measured;
  out.organForce_N = measured.organForce_N;
  out.organEvents = measured.organEvents;
  if (poked->second.threads == row.threads) {
    out.organStepMedian_ms = measured.organStepMedian_ms;
    out.organStepP99_ms = measured.organStepP99_ms;
    out.organStepsPerSecond = measured.organStepsPerSecond;
  } else {
    out.organStepMedian_ms = out.organStepP99_ms = out.organStepsPerSecond =
        std::numeric_limits<double>::quiet_NaN();
  }
  if (row.isOnOrganMesh()) {
    // No bundled poke for these rows (the continuum has no equilibrium at its 4 cm): the liver
    // poke is their cost.
    out.cost.nodes = measured.cost.nodes;
    out.cost.startup_s = measured.cost.startup_s;
    out.cost.stepMedian_ms = measured.organStepMedian_ms;
    out.cost.stepP99_ms = measured.organStepP99_ms;
    out.cost.stepsPerSecond = measured.organStepsPerSecond;
    out.cost.events = measured.organEvents;
  }
}

}  // namespace tissuesim::app
