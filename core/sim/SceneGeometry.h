// SPDX-License-Identifier: Apache-2.0
#pragma once
// What a scene's geometry builds, and only that: the simulation tet mesh (read, or generated
// from the surface), the visual surface welded and embedded in it when the scene names one, and
// the fixed nodes. The physics (springs, integrator, instrument) is assembled by the caller.

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
/// open or non-manifold surface to generate from, a fixed region that selects no node, or a
/// listed node out of range.
SceneGeometry loadSceneGeometry(const SceneDescription& scene);

}  // namespace tissuesim
