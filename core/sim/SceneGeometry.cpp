#include "sim/SceneGeometry.h"

#include <algorithm>

#include "mesh/LatticeMesher.h"
#include "mesh/SurfaceInspection.h"
#include "mesh/SurfaceReader.h"
#include "mesh/TetMeshFile.h"

namespace tissuesim {

SceneGeometry loadSceneGeometry(const SceneDescription& scene) {
  const std::string name = scene.source.string();
  SceneGeometry geometry;
  try {
    if (scene.surface) {
      TriangleSurface surface =
          readSurface(scene.surface->file, {scene.surface->metresPerUnit, scene.surface->part});
      weldVertices(surface, 1e-6 * inspectSurface(surface).boundingDiagonal_m);
      geometry.surface = std::move(surface);
    }
    if (scene.tetMesh) {
      geometry.mesh = readTetMesh(scene.tetMesh->file, scene.tetMesh->metresPerUnit);
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
  if (geometry.surface) geometry.embedding.emplace(geometry.mesh, geometry.surface->vertices_m);

  for (const int node : scene.fixed.nodes) {
    if (node >= geometry.mesh.nodeCount()) {
      throw SceneFileError(name + ": field 'fixed_region.nodes' lists node " +
                           std::to_string(node) + ", but the mesh has " +
                           std::to_string(geometry.mesh.nodeCount()) + " nodes");
    }
    geometry.fixedNodes.push_back(node);
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

}  // namespace tissuesim
