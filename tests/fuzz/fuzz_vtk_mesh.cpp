// SPDX-License-Identifier: Apache-2.0
// VTK's mesh files (render/VtkMeshFiles.h: legacy .vtk, XML .vtp and .vtu, read by VTK in a
// child process): any bytes, as one of the three (chosen by the first byte), read as a surface
// and as a tet mesh, give a mesh whose indices are in range or a MeshFileError.
#include <array>

#include "fuzz/FuzzInput.h"
#include "render/VtkMeshFiles.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tissuesim;
  if (size == 0) return 0;
  static constexpr std::array<const char*, 3> kExtensions = {".vtk", ".vtp", ".vtu"};
  const char* extension = kExtensions[data[0] % kExtensions.size()];
  const std::filesystem::path path = fuzz::asFile(data + 1, size - 1, extension);
  fuzz::expectOnlyOwnErrors<MeshFileError>([&] {
    const TriangleSurface surface = readVtkSurface(path);
    if (surface.triangles.size() > 0 &&
        (surface.triangles.minCoeff() < 0 || surface.triangles.maxCoeff() >= surface.vertexCount()))
      std::abort();
  });
  fuzz::expectOnlyOwnErrors<MeshFileError>([&] {
    const TetMesh mesh = readVtkTetMesh(path);
    if (mesh.tets.size() > 0 &&
        (mesh.tets.minCoeff() < 0 || mesh.tets.maxCoeff() >= mesh.nodeCount()))
      std::abort();
  });
  std::filesystem::remove(path);
  return 0;
}
