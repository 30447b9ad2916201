// SPDX-License-Identifier: Apache-2.0
#pragma once
// Shared fixtures: tet meshes from the test data.

#include <string>

#include "mesh/TetMesh.h"
#include "mesh/TetMeshFile.h"

namespace tissuesim::test {

/// A 20 x 20 x 10 mm block meshed by Gmsh (unstructured, 5 mm edges: no lattice cubes).
inline TetMesh unstructuredBlock() {
  return readTetMesh(std::string(TISSUESIM_TEST_DATA_DIR) + "/meshes/block-unstructured.msh");
}

}  // namespace tissuesim::test
