// SPDX-License-Identifier: Apache-2.0
#include "app/MeshCommand.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/CommandError.h"
#include "app/OutputFile.h"
#include "app/ProbeAtOption.h"
#include "app/SceneSession.h"
#include "fem/CurvedBoundary.h"
#include "fem/QuadraticTetMesh.h"
#include "mesh/LatticeMesher.h"
#include "mesh/LengthUnit.h"
#include "mesh/SurfaceInspection.h"
#include "mesh/SurfaceReader.h"
#include "mesh/TetMeshFile.h"
#include "render/VtkMeshFiles.h"
#include "sim/SceneGeometry.h"

namespace tissuesim::app {
namespace {

struct MeshOptions {
  std::string input;
  std::string scene;
  std::vector<double> probeAt_m;
  std::string output;
  double edgeLength_mm = 0.0;
  int targetSprings = 0;
  std::string units = "auto";
  double scale = 0.0;
  std::string part;
  double closeHoles_mm = -1.0;  ///< < 0: default, 2 % of the bounding-box diagonal
};

/// The scale to read with: given, or for --units auto the smallest candidate (millimetres), so
/// that no file is refused as too large before its unit is guessed (rescaled after).
double metresPerUnit(const MeshOptions& options) {
  if (options.scale > 0.0) return options.scale;
  if (options.units == "m") return 1.0;
  if (options.units == "cm") return 0.01;
  if (options.units == "mm" || options.units == "auto") return 0.001;
  throw CommandError("unknown --units '" + options.units +
                     "'; expected auto, m, cm or mm (or --scale)");
}

bool isGuessingUnits(const MeshOptions& options) {
  return options.scale <= 0.0 && options.units == "auto";
}

/// For --units auto: positions read in millimetres rescaled to the guessed unit, and what was
/// assumed said in the report. Throws when the result is not an organ's size in any unit.
void applyGuessedUnit(const std::string& input, Eigen::Matrix3Xd& positions_m) {
  std::optional<GuessedUnit> guessed;
  try {
    guessed = rescaleFromMillimetres(positions_m);
  } catch (const std::invalid_argument& error) {
    throw CommandError(input + ": " + error.what() + " (give --scale)");
  }
  if (!guessed) return;
  // With the report on stdout: stderr carries a failure's one line alone.
  std::printf(
      "assumed %s: the file is %.4g units across, %.3g cm in %s (give --units or --scale "
      "to say otherwise)\n",
      guessed->unit.name, guessed->diagonalInFileUnits,
      guessed->diagonalInFileUnits * guessed->unit.metresPerUnit * 100.0, guessed->unit.symbol);
}

void printQuality(const TetMesh& mesh, const char* what) {
  const TetQualityReport quality = inspectTets(mesh);
  std::printf("%s: %ld nodes, %ld tets, %ld springs\n", what, static_cast<long>(mesh.nodeCount()),
              static_cast<long>(mesh.tetCount()), static_cast<long>(countUniqueEdges(mesh)));
  std::printf(
      "  dihedral angles %.1f to %.1f deg, minimum radius ratio %.3f, %zu inverted tets, "
      "%zu slivers\n",
      quality.minDihedral_deg, quality.maxDihedral_deg, quality.minRadiusRatio,
      quality.invertedTets.size(), quality.slivers.size());
  std::printf("  volume %.6g cm^3\n", quality.totalVolume_m3 * 1e6);
}

bool isTetMeshInput(const std::filesystem::path& path) {
  if (isTetMeshFile(path) || path.extension() == ".vtu") return true;
  if (path.extension() != ".vtk") return false;
  try {  // a legacy .vtk may hold either a grid or a surface
    readVtkTetMesh(path);
    return true;
  } catch (const MeshFileError&) {
    return false;
  }
}

void writeMesh(const MeshOptions& options, const TetMesh& mesh) {
  if (options.output.empty()) return;
  try {
    writeGmsh(options.output, mesh);
  } catch (const MeshFileError& error) {
    throw CommandError(error.what());
  }
  std::printf("wrote %s (Gmsh 2.2, metres)\n", options.output.c_str());
}

/// The tet mesh a scene simulates, refined where its tool aims when the scene says so
/// (docs/scene-file.md, "Refined where the tool aims").
void runSceneMesh(const MeshOptions& options, const std::optional<Eigen::Vector3d>& probeAt_m) {
  SceneDescription scene = readScene(options.scene);
  if (probeAt_m) {
    if (!scene.instrument)
      throw CommandError("--probe-at: " + options.scene + " has no instrument");
    scene.instrument->tipStart_m = *probeAt_m;
  }
  SceneGeometry geometry;
  try {
    geometry = loadSceneGeometry(scene);
  } catch (const SceneFileError& error) {
    throw CommandError(error.what());
  }
  printQuality(geometry.mesh, scene.tetMesh && scene.tetMesh->refinement
                                  ? "scene tet mesh, refined where its tool aims"
                                  : "scene tet mesh");
  // The FEM at its own rate bends the quadratic body's boundary onto the drawn surface (the file
  // written is the linear mesh it starts from).
  if (scene.model == "fem-haptic-rate" && geometry.surface) {
    QuadraticTetMesh quadratic = makeQuadraticTetMesh(geometry.mesh);
    const CurvedBoundaryReport curved =
        curveBoundaryOnto(quadratic, geometry.mesh, *geometry.surface);
    std::printf(
        "  boundary bent onto the drawn surface: %d of %d edges (%d part of the way, %d left "
        "straight), the largest move %.2f mm\n",
        curved.bent + curved.shortened, curved.boundaryEdges, curved.shortened, curved.left,
        1e3 * curved.largestMove_m);
  }
  writeMesh(options, geometry.mesh);
}

void runMesh(const MeshOptions& options) {
  if (options.edgeLength_mm > 0.0 && options.targetSprings > 0) {
    throw CommandError("give --edge-length or --target-springs, not both");
  }
  if (options.input.empty() == options.scene.empty()) {
    throw CommandError("give --input or --scene, one of them");
  }
  const std::optional<Eigen::Vector3d> probeAt_m = probeAtOption(options.probeAt_m);
  if (probeAt_m && options.scene.empty()) throw CommandError("--probe-at is for --scene");
  if (!options.output.empty()) {
    if (std::filesystem::path(options.output).extension() != ".msh") {
      throw CommandError("--output " + options.output + ": only Gmsh 2.2 (.msh) is written");
    }
    checkOutputWritable(options.output, "--output");
  }
  if (!options.scene.empty()) {
    runSceneMesh(options, probeAt_m);
    return;
  }
  const std::filesystem::path input(options.input);
  const double scale = metresPerUnit(options);
  TetMesh mesh;
  try {
    if (isTetMeshInput(input)) {
      TetMeshReadReport report;
      mesh = isVtkMeshFile(input) ? readVtkTetMesh(input, scale, &report)
                                  : readTetMesh(input, scale, &report);
      if (isGuessingUnits(options)) applyGuessedUnit(options.input, mesh.nodes_m);
      std::printf(
          "read %s (%s)%s%s\n", options.input.c_str(), report.format.c_str(),
          report.skippedElements > 0
              ? (", skipped " + std::to_string(report.skippedElements) + " non-tet elements")
                    .c_str()
              : "",
          report.wasReoriented ? ", all tets re-oriented to positive volume" : "");
      printQuality(mesh, "tet mesh");
    } else {
      TriangleSurface surface = isVtkMeshFile(input) ? readVtkSurface(input, scale)
                                                     : readSurface(input, {scale, options.part});
      if (isGuessingUnits(options)) applyGuessedUnit(options.input, surface.vertices_m);
      const SurfaceReport before = inspectSurface(surface);
      const int merged = weldVertices(surface, 1e-6 * before.boundingDiagonal_m);
      SurfaceReport report = inspectSurface(surface);
      std::printf("surface %s: %s; %d duplicate vertices welded\n", options.input.c_str(),
                  report.summary().c_str(), merged);
      if (report.nonManifoldEdges > 0) {
        throw CommandError(
            options.input + ": the surface has " + std::to_string(report.nonManifoldEdges) +
            " non-manifold edges (three or more triangles on one edge); repair it first");
      }
      if (!report.holes.empty()) {
        const double limit = options.closeHoles_mm >= 0.0 ? options.closeHoles_mm / 1000.0
                                                          : 0.02 * report.boundingDiagonal_m;
        const int closed = closeSmallHoles(surface, limit);
        report = inspectSurface(surface);
        if (!report.holes.empty()) {
          std::string sizes;
          for (std::size_t h = 0; h < std::min<std::size_t>(report.holes.size(), 5); ++h) {
            char text[48];
            std::snprintf(text, sizeof text, "%s%.1f mm", h == 0 ? "" : ", ",
                          report.holes[h].diameter_m * 1e3);
            sizes += text;
          }
          throw CommandError(
              options.input + ": the surface is open: " + std::to_string(report.holes.size()) +
              " holes larger than " + std::to_string(limit * 1e3) + " mm (across: " + sizes +
              (report.holes.size() > 5 ? ", ..." : "") + "); close them or raise --close-holes-mm");
        }
        std::printf("closed %d small holes\n", closed);
      }
      double h = options.edgeLength_mm / 1000.0;
      if (h <= 0.0)
        h = edgeLengthForSpringCount(surface,
                                     options.targetSprings > 0 ? options.targetSprings : 5300);
      mesh = meshInterior(surface, {h});
      printQuality(mesh, "lattice tet mesh");
      const double enclosed = std::abs(enclosedVolume(surface));
      std::printf(
          "  edge length %.3f mm; tet volume / surface volume = %.3f (the surface is "
          "embedded in the mesh, not matched by it)\n",
          h * 1e3, inspectTets(mesh).totalVolume_m3 / enclosed);
    }
  } catch (const MeshFileError& error) {
    throw CommandError(error.what());
  } catch (const std::invalid_argument& error) {
    throw CommandError(options.input + ": " + error.what());
  }
  writeMesh(options, mesh);
}

}  // namespace

void registerMeshCommand(CLI::App& app) {
  auto options = std::make_shared<MeshOptions>();
  CLI::App* command = app.add_subcommand(
      "mesh",
      "Given a surface (OBJ, STL, PLY, glTF/GLB, OFF, VTK...), build a tet mesh inside it; given a "
      "tet mesh (.msh, .node/.ele, .vtk, .vtu), check it. Quality figures either way; --output "
      "writes Gmsh 2.2.");
  command->add_option("--input", options->input, "Surface or tet mesh file");
  command->add_option("--scene", options->scene,
                      "Instead of --input: the tet mesh this scene simulates (refined where its "
                      "tool aims when the scene says so)");
  command
      ->add_option("--probe-at", options->probeAt_m,
                   "With --scene: the tool's tip starts here (x,y,z in metres)")
      ->delimiter(',')
      ->expected(3);
  command->add_option("--output", options->output, "Tet mesh to write (.msh)");
  command->add_option("--edge-length", options->edgeLength_mm, "Lattice edge length in mm");
  command->add_option("--target-springs", options->targetSprings,
                      "About this many springs (default 5300 when no edge length)");
  command
      ->add_option("--units", options->units,
                   "Units of the file: m, cm, mm, or auto (the one that makes the mesh an "
                   "organ's size, about 15 cm across; said in the report)")
      ->capture_default_str();
  command->add_option("--scale", options->scale, "Metres per file unit (overrides --units)");
  command->add_option("--part", options->part, "Use one named part of a multi-part file");
  command->add_option("--close-holes-mm", options->closeHoles_mm,
                      "Close holes up to this size (default: 2 % of the bounding-box diagonal)");
  command->callback([options] { runMesh(*options); });
}

}  // namespace tissuesim::app
