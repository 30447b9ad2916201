// SPDX-License-Identifier: Apache-2.0
// The Gmsh .msh reader (versions 1, 2.2 and 4.1, ASCII): any bytes give a mesh or a
// MeshFileError.
#include "fuzz/FuzzInput.h"
#include "mesh/TetMeshFile.h"
#include "mesh/TriangleSurface.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tissuesim;
  const std::filesystem::path path = fuzz::asFile(data, size, ".msh");
  fuzz::expectOnlyOwnErrors<MeshFileError>([&] { readTetMesh(path); });
  return 0;
}
