// SPDX-License-Identifier: Apache-2.0
#include "app/OrganPokeCommand.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/OrganPokeExperiment.h"
#include "app/AssetPaths.h"
#include "app/CommandError.h"
#include "app/FemForceCache.h"
#include "app/LoadedTissue.h"
#include "app/OrganPoke.h"
#include "app/OutputFile.h"
#include "app/Percentile.h"
#include "app/ProbeAtOption.h"
#include "app/SceneSession.h"
#include "fem/FemModel.h"
#include "mesh/TetMesh.h"
#include "mesh/TriangleSurface.h"

namespace tissuesim::app {
namespace {

struct OrganPokeOptions {
  std::string scenePath;
  std::string femMeshPath;
  std::vector<double> depths_mm = kOrganPokeDepths_mm;
  /// The simulator on the drawn surface lattice-meshed to about these many springs; none: on
  /// the scene's own mesh.
  std::vector<int> springs;
  double speed_mm_s = 2.0;
  std::string outputPath;
  /// The FEM's forces read from here when it holds them for these inputs, else written here.
  std::string femCachePath;
  /// The FEM at its own rate and the contact at 1 kHz on this mesh (a row); empty: none.
  std::string hapticRateMeshPath;
  /// Each FEM update's latency (ms); 0: its wall time.
  double updateLatency_ms = 0.0;
  /// The haptic-rate row's contact points this far apart (mm).
  double hapticRateSpacing_mm = 1.0;
  /// Its FEM updates' Newton iterations.
  int hapticRateIterations = HapticRateSettings{}.newtonIterations;
  /// Its body's bulk modulus (kPa; 0: the reference's).
  double hapticRateVolumeTerm_kPa = 0.0;
  /// Its body linear between updates (no stiffening handed to the contact).
  bool isHapticRateLinear = false;
  /// The probe's tip starts here (m) instead of at the scene's tip_start_m; empty: there.
  std::vector<double> probeAt_m;
  /// The organ under the scene's gravity and on its tray (the reference and the simulator).
  bool isWeighted = false;
};

/// The deepest poke the command takes (mm): past it the probe nears the far side of an organ.
constexpr double kMaxDepth_mm = 30.0;

/// The FEM reference's forces at `depths_m`: from --fem-cache when it holds them for these
/// inputs, else solved (minutes) and kept there.
std::vector<double> femForces(const OrganPokeOptions& options, const SceneDescription& scene,
                              const LoadedTissue& tissue, const std::vector<double>& depths_m) {
  const OrganPokeSetup setup = organPokeSetup(scene, depths_m, tissue.parameters.density_kg_m3);
  const double bulkModulus_Pa = defaultFemBulkModulus(tissue.energy);
  const std::uint64_t key = femReferenceKey(scene, options.femMeshPath, setup, bulkModulus_Pa);
  if (!options.femCachePath.empty()) {
    std::string why;
    std::optional<std::vector<double>> kept =
        readFemForceCache(options.femCachePath, key, options.depths_mm, why);
    if (kept) {
      std::fprintf(stderr, "fem: the forces from %s\n", options.femCachePath.c_str());
      return *kept;
    }
    std::fprintf(stderr, "fem: not from %s: %s\n", options.femCachePath.c_str(), why.c_str());
  }
  // Read only to solve: a kept reference needs the mesh file's bytes alone (its key).
  const TetMesh organ = readOrganMesh(options.femMeshPath);
  Eigen::Vector3d entry_m;
  if (!firstCrossing(organ.nodes_m, boundaryFaces(organ), setup.tipStart_m,
                     setup.direction.normalized(), entry_m))
    throw CommandError(options.femMeshPath +
                       ": the probe's axis does not meet the organ's surface");
  std::fprintf(stderr, "organ-poke: %s, %s, a %.1f mm probe along its axis; the FEM on %s\n",
               scene.name.c_str(),
               options.isWeighted ? (scene.tray ? "under gravity on its tray" : "under gravity")
                                  : "weightless",
               1e3 * setup.probeRadius_m, options.femMeshPath.c_str());
  IndentationCurve fem;
  try {
    fem = pokeOrganFem(tissue.energy, organ, setup, bulkModulus_Pa,
                       [](double depth_m, double force_N) {
                         std::fprintf(stderr, "fem: %.1f mm, %.4f N\n", 1e3 * depth_m, force_N);
                       });
  } catch (const std::invalid_argument& error) {
    throw CommandError(options.femMeshPath + ": " + error.what());
  }
  std::fprintf(
      stderr,
      "fem: %d nodes, %d quadratic tets, %.1f s; %ld Newton iterations at %.1f ms each; %d "
      "of its solves stopped unconverged, the largest net force left on a node %.2g N\n",
      fem.nodes, fem.elements, fem.seconds, fem.newtonIterations,
      fem.newtonIterations > 0 ? 1e3 * fem.solving_s / fem.newtonIterations : 0.0,
      fem.unconvergedPoints, fem.worstResidual_N);
  if (options.isWeighted) {
    std::fprintf(stderr,
                 "fem: settled under its weight in %ld Newton iterations, the entry point %.2f "
                 "mm from where it was at rest\n",
                 fem.settlingIterations, 1e3 * fem.entrySag_m);
  }
  // A probe that meets no surface node (the node penalty) on a mesh whose nodes lie further
  // apart than the probe is wide there reads nothing: no reference to compare with.
  for (std::size_t d = 0; d < fem.force_N.size(); ++d) {
    if (!(fem.force_N[d] > 0.0)) {
      char depth[32];
      std::snprintf(depth, sizeof depth, "%g", options.depths_mm[d]);
      throw CommandError(options.femMeshPath + ": the reference reads no force at " + depth +
                         " mm: its surface nodes lie too far apart where the probe meets it "
                         "(grade the mesh towards there: assets/meshes/README.md)");
    }
  }
  if (!options.femCachePath.empty()) {
    // A millionth of the deepest force left unbalanced moves no kept digit that matters; more,
    // and the forces are no reference to keep.
    const double kept_N = 1e-6 * std::abs(fem.force_N.back());
    if (fem.worstResidual_N <= kept_N) {
      writeFemForceCache(options.femCachePath, key, options.depths_mm, fem.force_N);
      std::fprintf(stderr, "fem: the forces kept in %s\n", options.femCachePath.c_str());
    } else {
      std::fprintf(stderr, "fem: not kept in %s: a solve left more than %.2g N unbalanced\n",
                   options.femCachePath.c_str(), kept_N);
    }
  }
  return fem.force_N;
}

void runOrganPoke(const OrganPokeOptions& options) {
  std::vector<double> depths_m;
  for (const double depth : options.depths_mm) {
    if (!(depth > (depths_m.empty() ? 0.0 : 1e3 * depths_m.back())) || depth > kMaxDepth_mm)
      throw CommandError("--depths-mm must increase, each in (0, 30] mm");
    depths_m.push_back(depth / 1000.0);
  }
  for (const int count : options.springs) {
    if (count < 100 || count > 200000)
      throw CommandError("--springs " + std::to_string(count) +
                         " is out of range; expected 100 to 200000");
  }
  if (!(options.speed_mm_s > 0.0) || options.speed_mm_s > 1000.0)
    throw CommandError("--speed-mm-s must be in (0, 1000]");
  if (!(options.updateLatency_ms >= 0.0) || options.updateLatency_ms > 10000.0)
    throw CommandError("--update-latency-ms must be in [0, 10000]");
  if (!(options.hapticRateSpacing_mm > 0.0) || options.hapticRateSpacing_mm > 10.0)
    throw CommandError("--haptic-rate-spacing-mm must be in (0, 10]");
  if (options.hapticRateIterations < 0 || options.hapticRateIterations > 20)
    throw CommandError("--haptic-rate-iterations must be in [0, 20]");
  if (!(options.hapticRateVolumeTerm_kPa >= 0.0) || options.hapticRateVolumeTerm_kPa > 1e7)
    throw CommandError("--haptic-rate-volume-term-kpa must be in [0, 1e7]");
  const std::optional<Eigen::Vector3d> probeAt_m = probeAtOption(options.probeAt_m);
  if (!options.outputPath.empty()) checkOutputWritable(options.outputPath, "--output");
  if (!options.femCachePath.empty()) checkOutputWritable(options.femCachePath, "--fem-cache");

  if (options.isWeighted && !options.hapticRateMeshPath.empty())
    throw CommandError(
        "--haptic-rate-mesh runs weightless; with --weighted, poke a scene whose "
        "effects.model is fem-haptic-rate");
  // Weightless and on nothing but its fixed region (the continuum reference's conditions), or
  // as the scene holds it.
  SceneDescription scene = options.isWeighted ? weightedPokeScene(readScene(options.scenePath))
                                              : weightlessPokeScene(readScene(options.scenePath));
  if (probeAt_m) scene.instrument->tipStart_m = *probeAt_m;
  // The haptic-rate row's mesh read before the reference is solved (minutes): a bad file fails
  // at once.
  std::optional<TetMesh> hapticRateOrgan;
  if (!options.hapticRateMeshPath.empty())
    hapticRateOrgan = readOrganMesh(options.hapticRateMeshPath);
  const LoadedTissue tissue(scene.tissue.string());
  const std::vector<double> femForce_N = femForces(options, scene, tissue, depths_m);
  // The simulator as the scene sets it up, on its own mesh or on the surface meshed anew.
  struct Row {
    std::string mesh;
    SceneDescription scene;
  };
  std::vector<Row> rows;
  if (options.springs.empty()) rows.push_back({"scene", scene});
  for (const int count : options.springs) {
    Row row{"springs ~" + std::to_string(count), scene};
    row.scene.tetMesh.reset();
    row.scene.targetSprings = count;
    rows.push_back(row);
  }
  std::string csv = "simulator_mesh,depth_mm,fem_force_n,simulator_force_n,error_vs_fem_percent\n";
  for (const Row& row : rows) {
    const SimulatorPoke poke = pokeSimulator(row.scene, depths_m, options.speed_mm_s / 1000.0);
    const std::vector<double>& simulator = poke.force_N;
    const std::string kinds = poke.eventKinds.empty() ? "" : " (" + poke.eventKinds + ")";
    std::fprintf(stderr,
                 "simulator (%s): %.1f s, %ld steps at %.3g ms a step, %ld instability events%s, "
                 "the probe at %g mm/s\n",
                 row.mesh.c_str(), poke.seconds, poke.steps, 1e3 * poke.stepping_s / poke.steps,
                 poke.events, kinds.c_str(), options.speed_mm_s);
    if (poke.updates > 0) {
      std::fprintf(stderr,
                   "simulator (%s): %d quadratic nodes; %ld FEM updates at %.0f ms mean, each "
                   "used %g ms after it started (the steps' times leave out their wait for it)\n",
                   row.mesh.c_str(), poke.nodes, poke.updates, poke.updateMean_ms,
                   1e3 * row.scene.femUpdateLatency_s);
    }
    for (std::size_t d = 0; d < depths_m.size(); ++d) {
      const double error = 100.0 * (simulator[d] / femForce_N[d] - 1.0);
      std::fprintf(stderr, "%5.1f mm: fem %.4f N, simulator %.4f N (%+.0f %%)\n",
                   options.depths_mm[d], femForce_N[d], simulator[d], error);
      char line[200];
      std::snprintf(line, sizeof line, "%s,%.6g,%.6g,%.6g,%.3f\n", row.mesh.c_str(),
                    options.depths_mm[d], femForce_N[d], simulator[d], error);
      csv += line;
    }
  }
  if (hapticRateOrgan) {
    const TetMesh& organ = *hapticRateOrgan;
    HapticRateSettings settings;
    settings.speed_m_s = options.speed_mm_s / 1000.0;
    settings.updateLatency_s = options.updateLatency_ms / 1000.0;
    settings.newtonIterations = options.hapticRateIterations;
    settings.isStiffeningBetweenUpdates = !options.isHapticRateLinear;
    OrganPokeSetup setup = organPokeSetup(scene, depths_m);
    setup.contactSpacing_m = options.hapticRateSpacing_mm / 1000.0;
    HapticRatePoke poke;
    try {
      const double bulkModulus_Pa = options.hapticRateVolumeTerm_kPa > 0.0
                                        ? 1000.0 * options.hapticRateVolumeTerm_kPa
                                        : defaultFemBulkModulus(tissue.energy);
      poke = pokeOrganHapticRate(tissue.energy, organ, setup, bulkModulus_Pa, settings);
    } catch (const std::invalid_argument& error) {
      throw CommandError(options.hapticRateMeshPath + ": " + error.what());
    }
    const auto quantile = [&](double share) { return percentile(poke.stepTimes_ms, share); };
    char latency[64] = "their own wall time";
    if (options.updateLatency_ms > 0.0)
      std::snprintf(latency, sizeof latency, "%g ms", options.updateLatency_ms);
    const double meanUpdate_ms = poke.updates > 0 ? 1e3 * poke.updating_s / poke.updates : 0.0;
    // What decides whether the staggered iteration holds: the probe's travel between the FEM's
    // linearisations (docs/performance-details.md measures its reach).
    const double travel_mm =
        options.speed_mm_s *
        (options.updateLatency_ms > 0.0 ? options.updateLatency_ms : meanUpdate_ms) / 1000.0;
    std::fprintf(stderr,
                 "haptic rate (%s): %d nodes; %ld contact steps at %.3g ms median, %.3g ms p99, "
                 "%ld unsettled; %ld FEM updates at %.0f ms mean, %.0f ms longest, each used "
                 "%s after it started (%.2f mm of the probe's travel), %ld without a step; at "
                 "most %d contact nodes; %.1f s\n",
                 options.hapticRateMeshPath.c_str(), poke.nodes, poke.steps, quantile(0.5),
                 quantile(0.99), poke.unconvergedSteps, poke.updates, meanUpdate_ms,
                 1e3 * poke.longestUpdate_s, latency, travel_mm, poke.unsteppedUpdates,
                 poke.maxCandidates, poke.seconds);
    for (std::size_t d = 0; d < depths_m.size(); ++d) {
      const double error = 100.0 * (poke.force_N[d] / femForce_N[d] - 1.0);
      std::fprintf(stderr, "%5.1f mm: fem %.4f N, haptic rate %.4f N (%+.0f %%)\n",
                   options.depths_mm[d], femForce_N[d], poke.force_N[d], error);
      char line[200];
      std::snprintf(line, sizeof line, "haptic-rate,%.6g,%.6g,%.6g,%.3f\n", options.depths_mm[d],
                    femForce_N[d], poke.force_N[d], error);
      csv += line;
    }
  }
  if (options.outputPath.empty()) {
    std::fputs(csv.c_str(), stdout);
  } else {
    writeTextFile(options.outputPath, "--output", csv);
  }
}

}  // namespace

void registerOrganPokeCommand(CLI::App& app) {
  auto options = std::make_shared<OrganPokeOptions>();
  CLI::App* command = app.add_subcommand(
      "organ-poke",
      "A scene's organ, weightless (or with --weighted under its gravity and on its tray), poked "
      "along its instrument's axis: the FEM reference on a conformal tet mesh of its drawn "
      "surface against the simulator as the scene sets it up; the probe's force at each depth "
      "below the surface and the simulator's error (CSV; a table on stderr).");
  options->scenePath = bundledAsset("scenes/liver-poke.json").string();
  command->add_option("--scene", options->scenePath, "Scene file (JSON)")->capture_default_str();
  options->femMeshPath = bundledAsset("meshes/liver-fem.msh").string();
  command
      ->add_option("--fem-mesh", options->femMeshPath,
                   "The organ meshed conformally with its drawn surface, graded towards the "
                   "poke (assets/meshes/README.md), metres")
      ->capture_default_str();
  command->add_option("--depths-mm", options->depths_mm, "Depths below the surface, increasing")
      ->delimiter(',')
      ->capture_default_str();
  command
      ->add_option("--springs", options->springs,
                   "The simulator on the drawn surface lattice-meshed to about these many springs "
                   "(default: on the scene's own mesh)")
      ->delimiter(',');
  command->add_option("--speed-mm-s", options->speed_mm_s, "The simulator's probe speed")
      ->capture_default_str();
  command->add_option("--output", options->outputPath, "CSV file (default: stdout)");
  command->add_option("--fem-cache", options->femCachePath,
                      "The FEM's forces: read from this file when it holds them for the same "
                      "scene, tissue, FEM mesh and depths, else solved and added to it");
  command->add_option("--haptic-rate-mesh", options->hapticRateMeshPath,
                      "Add a row: the FEM (quadratic tets) on this mesh at its own rate, the "
                      "probe's contact at 1 kHz against its compliance condensed near the probe");
  command->add_option("--update-latency-ms", options->updateLatency_ms,
                      "With --haptic-rate-mesh: each FEM update answers this long after it "
                      "starts (default 0: its own wall time)");
  command
      ->add_option("--haptic-rate-spacing-mm", options->hapticRateSpacing_mm,
                   "With --haptic-rate-mesh: its contact's points between the quadratic "
                   "surface nodes this far apart")
      ->capture_default_str();
  command
      ->add_option("--haptic-rate-iterations", options->hapticRateIterations,
                   "With --haptic-rate-mesh: each FEM update's Newton iterations (0: the body "
                   "linearised where the contact has it)")
      ->capture_default_str();
  command->add_option("--haptic-rate-volume-term-kpa", options->hapticRateVolumeTerm_kPa,
                      "With --haptic-rate-mesh: its body's bulk modulus (default: the "
                      "reference's)");
  command
      ->add_option("--probe-at", options->probeAt_m,
                   "The probe's tip starts here (x,y,z in metres; default: the scene's "
                   "tip_start_m), along the scene's direction; the reference's mesh should be "
                   "graded towards where it meets the organ (assets/meshes/README.md)")
      ->delimiter(',')
      ->expected(3);
  command->add_flag("--weighted", options->isWeighted,
                    "The organ under the scene's gravity and on its tray, settled before the probe "
                    "comes down, in the reference and the simulator alike; the depths below where "
                    "the probe's axis meets the settled surface (default: weightless)");
  command->add_flag("--haptic-rate-linear", options->isHapticRateLinear,
                    "With --haptic-rate-mesh: its body linear between updates (without the "
                    "stiffening each update measures)");
  command->callback([options] { runOrganPoke(*options); });
}

}  // namespace tissuesim::app
