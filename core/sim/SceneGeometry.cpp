// SPDX-License-Identifier: Apache-2.0
#include "sim/SceneGeometry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mesh/LatticeMesher.h"
#include "mesh/LengthUnit.h"
#include "mesh/SurfaceInspection.h"
#include "mesh/SurfaceReader.h"
#include "mesh/TetMeshFile.h"
#include "mesh/TetRefinement.h"

namespace tissuesim {

namespace {

/// The scale to read a mesh file with: the scene's, or millimetres (the smallest candidate, so
/// no file is refused as too large before its unit is guessed).
double readingScale(const SceneMeshSource& source) {
  return source.metresPerUnit > 0.0 ? source.metresPerUnit : 0.001;
}

/// Where the scene gave no unit: positions read in millimetres rescaled to the unit that makes the
/// mesh an organ's size, and what was assumed added to `assumptions`.
void applyGuessedUnit(const SceneMeshSource& source, const std::string& sceneName,
                      Eigen::Matrix3Xd& positions_m, std::vector<std::string>& assumptions) {
  if (source.metresPerUnit > 0.0) return;
  const std::string file = source.file.lexically_normal().string();
  std::optional<GuessedUnit> guessed;
  try {
    guessed = rescaleFromMillimetres(positions_m);
  } catch (const std::invalid_argument& error) {
    throw SceneFileError(sceneName + ": " + file + ": " + error.what() + " (set metres_per_unit)");
  }
  if (!guessed) return;
  char line[512];
  std::snprintf(line, sizeof line,
                "%s: assumed %s (the file is %.4g units across: %.3g cm); set metres_per_unit in "
                "the scene to say otherwise",
                file.c_str(), guessed->unit.name, guessed->diagonalInFileUnits,
                guessed->diagonalInFileUnits * guessed->unit.metresPerUnit * 100.0);
  assumptions.emplace_back(line);
}

}  // namespace

SceneGeometry loadSceneGeometry(const SceneDescription& scene) {
  return completeSceneGeometry(scene, readSceneGeometry(scene));
}

SceneGeometry readSceneGeometry(const SceneDescription& scene) {
  const std::string name = scene.source.string();
  SceneGeometry geometry;
  try {
    if (scene.surface) {
      TriangleSurface surface =
          readSurface(scene.surface->file, {readingScale(*scene.surface), scene.surface->part});
      applyGuessedUnit(*scene.surface, name, surface.vertices_m, geometry.assumptions);
      weldVertices(surface, 1e-6 * inspectSurface(surface).boundingDiagonal_m);
      geometry.surface = std::move(surface);
    }
    if (scene.tetMesh) {
      geometry.mesh = readTetMesh(scene.tetMesh->file, readingScale(*scene.tetMesh));
      applyGuessedUnit(*scene.tetMesh, name, geometry.mesh.nodes_m, geometry.assumptions);
    } else {
      const SurfaceReport report = inspectSurface(*geometry.surface);
      if (!report.isClosedManifold()) {
        throw SceneFileError(name + ": field 'generate_tet_mesh' needs a closed surface; " +
                             scene.surface->file.string() + " has " + report.summary());
      }
      geometry.mesh = meshInterior(
          *geometry.surface, {edgeLengthForSpringCount(*geometry.surface, scene.targetSprings)});
    }
  } catch (const MeshFileError& error) {
    throw SceneFileError(name + ": " + error.what());
  } catch (const std::invalid_argument& error) {
    throw SceneFileError(name + ": " + error.what());
  }
  return geometry;
}

SceneGeometry completeSceneGeometry(const SceneDescription& scene, SceneGeometry geometry) {
  const std::string name = scene.source.string();
  // Listed fixed nodes are the file's: the refinement's come after them.
  const Eigen::Index fileNodeCount = geometry.mesh.nodeCount();
  Eigen::Matrix2Xi splitEdges(2, 0);
  if (scene.tetMesh && scene.tetMesh->refinement) {
    const SceneTetRefinement& refinement = *scene.tetMesh->refinement;
    TetMeshGrading grading;
    if (!firstOrganCrossing(geometry, scene.instrument->tipStart_m, scene.instrument->direction,
                            grading.centre_m)) {
      throw SceneFileError(name +
                           ": field 'tet_mesh.refine_towards_tool': the instrument's axis from "
                           "tip_start_m along its direction misses the organ");
    }
    grading.finest_m = refinement.finest_m;
    grading.growth = refinement.growth;
    grading.coarsest_m = refinement.coarsest_m;
    try {
      RefinedTetMesh refined = refineTetMesh(geometry.mesh, grading, &*geometry.surface);
      geometry.mesh = std::move(refined.mesh);
      splitEdges = std::move(refined.splitEdges);
    } catch (const std::invalid_argument& error) {
      throw SceneFileError(name + ": " + scene.tetMesh->file.lexically_normal().string() + ": " +
                           error.what());
    }
  }
  if (geometry.surface) geometry.embedding.emplace(geometry.mesh, geometry.surface->vertices_m);

  for (const int node : scene.fixed.nodes) {
    if (node >= fileNodeCount) {
      throw SceneFileError(name + ": field 'fixed_region.nodes' lists node " +
                           std::to_string(node) + ", but the mesh has " +
                           std::to_string(fileNodeCount) + " nodes");
    }
    geometry.fixedNodes.push_back(node);
  }
  // A node the refinement put between two listed nodes is held with them.
  if (!scene.fixed.nodes.empty()) {
    std::vector<char> isListed(static_cast<std::size_t>(geometry.mesh.nodeCount()), 0);
    for (const int node : geometry.fixedNodes) isListed[static_cast<std::size_t>(node)] = 1;
    const Eigen::Index firstNew = geometry.mesh.nodeCount() - splitEdges.cols();
    for (Eigen::Index k = 0; k < splitEdges.cols(); ++k) {
      if (isListed[static_cast<std::size_t>(splitEdges(0, k))] != 0 &&
          isListed[static_cast<std::size_t>(splitEdges(1, k))] != 0) {
        isListed[static_cast<std::size_t>(firstNew + k)] = 1;
        geometry.fixedNodes.push_back(static_cast<int>(firstNew + k));
      }
    }
  }
  if (scene.fixed.box_m) {
    const std::size_t before = geometry.fixedNodes.size();
    for (Eigen::Index i = 0; i < geometry.mesh.nodeCount(); ++i) {
      if (scene.fixed.box_m->contains(geometry.mesh.nodes_m.col(i)))
        geometry.fixedNodes.push_back(static_cast<int>(i));
    }
    if (geometry.fixedNodes.size() == before) {
      throw SceneFileError(name + ": field 'fixed_region' box selects no node of the mesh");
    }
  }
  std::sort(geometry.fixedNodes.begin(), geometry.fixedNodes.end());
  geometry.fixedNodes.erase(std::unique(geometry.fixedNodes.begin(), geometry.fixedNodes.end()),
                            geometry.fixedNodes.end());
  return geometry;
}

bool firstOrganCrossing(const SceneGeometry& geometry, const Eigen::Vector3d& from_m,
                        const Eigen::Vector3d& direction, Eigen::Vector3d& crossing_m) {
  if (geometry.surface) {
    return firstCrossing(geometry.surface->vertices_m, geometry.surface->triangles, from_m,
                         direction, crossing_m);
  }
  return firstCrossing(geometry.mesh.nodes_m, boundaryFaces(geometry.mesh), from_m, direction,
                       crossing_m);
}

bool firstOrganCrossing(const SceneGeometry& geometry, const Eigen::Matrix3Xd& x,
                        const Eigen::Vector3d& from_m, const Eigen::Vector3d& direction,
                        Eigen::Vector3d& crossing_m) {
  if (geometry.surface && geometry.embedding) {
    Eigen::Matrix3Xd vertices(3, geometry.surface->vertices_m.cols());
    geometry.embedding->apply(x, vertices);
    return firstCrossing(vertices, geometry.surface->triangles, from_m, direction, crossing_m);
  }
  return firstCrossing(x, boundaryFaces(geometry.mesh), from_m, direction, crossing_m);
}

}  // namespace tissuesim
