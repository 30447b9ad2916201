// SPDX-License-Identifier: Apache-2.0
#pragma once
// What a scene's geometry builds, and only that: the simulation tet mesh (read, or generated
// from the surface; refined where the instrument first aims when the scene asks, its boundary's
// new nodes on the drawn surface), the visual surface welded and embedded in it when the scene
// names one, and the fixed nodes (a listed node's index is the file's; a node the refinement put
// between two listed ones is held too). The physics (springs, integrator, instrument) is assembled
// by the caller.

#include <optional>
#include <string>
#include <vector>

#include "mesh/SurfaceEmbedding.h"
#include "mesh/TriangleSurface.h"
#include "sim/SceneFile.h"

namespace tissuesim {

struct SceneGeometry {
  TetMesh mesh;
  std::optional<TriangleSurface> surface;     ///< welded; only when the scene names one
  std::optional<SurfaceEmbedding> embedding;  ///< idem
  std::vector<int> fixedNodes;                ///< sorted, unique
  /// What was assumed while loading, one line each (a mesh file's unit, guessed from its size
  /// where the scene gives no metres_per_unit): for the user to see.
  std::vector<std::string> assumptions;
};

/// @throws SceneFileError naming the scene (and MeshFileError's text for its meshes): bad mesh,
/// open or non-manifold surface to generate from, an instrument's axis that misses the organ
/// where the mesh is to be refined, a fixed region that selects no node, or a
/// listed node out of range.
SceneGeometry loadSceneGeometry(const SceneDescription& scene);
/// Its two halves: the scene's files read (the surface welded, the tet mesh as read or generated;
/// no embedding, no fixed nodes), and that completed (refined where the instrument aims, the
/// surface embedded, the fixed nodes chosen). A scene refined again where its tool aims keeps
/// the first and completes it anew, so that files changed on disk since it opened play no part.
/// @throws SceneFileError as loadSceneGeometry.
SceneGeometry readSceneGeometry(const SceneDescription& scene);
SceneGeometry completeSceneGeometry(const SceneDescription& scene, SceneGeometry read);

/// Where the ray from `from_m` along unit `direction` first meets the organ at rest: its drawn
/// surface where the scene names one (what the user sees the tool touch, and what the FEM
/// reference's mesh is conformal to), else the tet mesh's boundary. The liver poke's entry
/// point: its depths are measured below it, for every model alike (a model's own boundary, a
/// coarse tet mesh's chords, lies a little inside the drawn surface, and measured from there a
/// model would be credited with that offset). false when the ray misses.
bool firstOrganCrossing(const SceneGeometry& geometry, const Eigen::Vector3d& from_m,
                        const Eigen::Vector3d& direction, Eigen::Vector3d& crossing_m);
/// The same with the organ where its tet mesh's nodes are at x (3 by #V, m): the drawn surface
/// carried by its embedding, else the mesh's boundary. The liver poke's entry point on the organ
/// settled under its weight.
bool firstOrganCrossing(const SceneGeometry& geometry, const Eigen::Matrix3Xd& x,
                        const Eigen::Vector3d& from_m, const Eigen::Vector3d& direction,
                        Eigen::Vector3d& crossing_m);

}  // namespace tissuesim
