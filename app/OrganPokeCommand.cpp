// SPDX-License-Identifier: Apache-2.0
#include "app/OrganPokeCommand.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/OrganPokeExperiment.h"
#include "app/AssetPaths.h"
#include "app/CommandError.h"
#include "app/LoadedTissue.h"
#include "app/OutputFile.h"
#include "app/SceneSession.h"
#include "fem/FemModel.h"
#include "mesh/TetMeshFile.h"
#include "mesh/TriangleSurface.h"

namespace tissuesim::app {
namespace {

struct OrganPokeOptions {
  std::string scenePath;
  std::string femMeshPath;
  std::vector<double> depths_mm{1.0, 2.0, 3.0, 4.0, 5.0, 10.0};
  /// The simulator on the drawn surface lattice-meshed to about these many springs; none: on
  /// the scene's own mesh.
  std::vector<int> springs;
  double speed_mm_s = 2.0;
  std::string outputPath;
};

/// The deepest poke the command takes (mm): past it the probe nears the far side of an organ.
constexpr double kMaxDepth_mm = 30.0;

/// The simulator's force along the probe's axis at each depth below where the axis meets the
/// drawn surface (or the tet mesh's boundary), the probe driven at `speed_m_s` from its start;
/// interpolated between the steps either side of each depth.
std::vector<double> simulatorForces(const SceneDescription& scene,
                                    const std::vector<double>& depths_m, double speed_m_s,
                                    double& seconds, long& events) {
  const auto start = std::chrono::steady_clock::now();
  SceneSession session(scene, "", InstrumentDriver::Script);
  Simulation& simulation = session.simulation();
  const SceneInstrument& tool = *scene.instrument;
  const SceneGeometry& geometry = simulation.geometry();
  Eigen::Vector3d entry;
  const bool meets = geometry.surface
                         ? firstCrossing(geometry.surface->vertices_m, geometry.surface->triangles,
                                         tool.tipStart_m, tool.direction, entry)
                         : firstCrossing(geometry.mesh.nodes_m, boundaryFaces(geometry.mesh),
                                         tool.tipStart_m, tool.direction, entry);
  if (!meets) {
    throw CommandError("the instrument's axis in " + scene.source.string() +
                       " does not meet the organ's surface");
  }
  const double approach_m = (entry - tool.tipStart_m).dot(tool.direction);
  const double travel_m = approach_m + depths_m.back() + simulation.timeStep_s() * speed_m_s;
  session.useScript(InstrumentScript::poke(InstrumentPose{tool.tipStart_m, tool.direction, false},
                                           travel_m, travel_m / speed_m_s));
  std::vector<double> forces;
  double lastDepth = -approach_m, lastForce = 0.0;
  // A refused step leaves the time, and so the probe, where it was: count attempts, not steps.
  const long attemptLimit =
      2 * static_cast<long>(std::ceil(travel_m / speed_m_s / simulation.timeStep_s()));
  for (long attempt = 0; forces.size() < depths_m.size(); ++attempt) {
    if (attempt > attemptLimit) {
      throw CommandError("the simulator of " + scene.source.string() + " did not reach " +
                         std::to_string(1e3 * depths_m[forces.size()]) + " mm (" +
                         std::to_string(simulation.eventCount()) + " instability events)");
    }
    const StepOutcome outcome = simulation.step();
    const double depth = (simulation.instrumentPose().tip_m - entry).dot(tool.direction);
    const double force = -outcome.contact.toolForce_N.dot(tool.direction);
    while (forces.size() < depths_m.size() && depth >= depths_m[forces.size()]) {
      const double target = depths_m[forces.size()];
      forces.push_back(lastForce +
                       (force - lastForce) * (target - lastDepth) / (depth - lastDepth));
    }
    lastDepth = depth;
    lastForce = force;
  }
  events = static_cast<long>(simulation.eventCount());
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return forces;
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
  if (!options.outputPath.empty()) checkOutputWritable(options.outputPath, "--output");

  SceneDescription scene = readScene(options.scenePath);
  if (!scene.instrument)
    throw CommandError("the scene " + scene.source.string() + " has no instrument to poke with");
  if (!scene.fixed.box_m) {
    throw CommandError("the scene " + scene.source.string() +
                       " holds listed nodes; the organ poke needs its fixed region as a box");
  }
  // Weightless and on nothing but its fixed region: the continuum reference's conditions.
  scene.gravity_m_s2.setZero();
  scene.tray.reset();

  TetMesh organ;
  try {
    organ = readTetMesh(options.femMeshPath);
  } catch (const MeshFileError& error) {
    throw CommandError(error.what());
  }
  const LoadedTissue tissue(scene.tissue.string());
  const StrainEnergy& energy = tissue.energy;
  OrganPokeSetup setup;
  setup.tipStart_m = scene.instrument->tipStart_m;
  setup.direction = scene.instrument->direction;
  setup.probeRadius_m = scene.instrument->shaftRadius_m;
  setup.fixedBox_m = *scene.fixed.box_m;
  setup.depths_m = depths_m;
  std::fprintf(stderr,
               "organ-poke: %s, weightless, a %.1f mm probe from its start; the FEM on %s\n",
               scene.name.c_str(), 1e3 * setup.probeRadius_m, options.femMeshPath.c_str());
  IndentationCurve fem;
  try {
    fem = pokeOrganFem(energy, organ, setup, defaultFemBulkModulus(energy),
                       [](double depth_m, double force_N) {
                         std::fprintf(stderr, "fem: %.1f mm, %.4f N\n", 1e3 * depth_m, force_N);
                       });
  } catch (const std::invalid_argument& error) {
    throw CommandError(options.femMeshPath + ": " + error.what());
  }
  std::fprintf(stderr, "fem: %d nodes, %d quadratic tets, %.1f s%s\n", fem.nodes, fem.elements,
               fem.seconds, fem.unconvergedPoints > 0 ? " (some solves stopped unconverged)" : "");
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
    double seconds = 0.0;
    long events = 0;
    const std::vector<double> simulator =
        simulatorForces(row.scene, depths_m, options.speed_mm_s / 1000.0, seconds, events);
    std::fprintf(stderr, "simulator (%s): %.1f s, %ld instability events, the probe at %g mm/s\n",
                 row.mesh.c_str(), seconds, events, options.speed_mm_s);
    for (std::size_t d = 0; d < depths_m.size(); ++d) {
      const double error = 100.0 * (simulator[d] / fem.force_N[d] - 1.0);
      std::fprintf(stderr, "%5.1f mm: fem %.4f N, simulator %.4f N (%+.0f %%)\n",
                   options.depths_mm[d], fem.force_N[d], simulator[d], error);
      char line[200];
      std::snprintf(line, sizeof line, "%s,%.6g,%.6g,%.6g,%.3f\n", row.mesh.c_str(),
                    options.depths_mm[d], fem.force_N[d], simulator[d], error);
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
      "A scene's organ, weightless, poked along its instrument's axis: the FEM reference on a "
      "conformal tet mesh of its drawn surface against the simulator as the scene sets it up; "
      "the probe's force at each depth below the surface and the simulator's error (CSV; a "
      "table on stderr).");
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
  command->callback([options] { runOrganPoke(*options); });
}

}  // namespace tissuesim::app
