// SPDX-License-Identifier: Apache-2.0
// The surface-loading path (assimp in a child process, core/mesh/IsolatedMeshRead.h): any bytes,
// as any of the formats read here (chosen by the first byte), give a surface or a MeshFileError.
// The child's crashes and hangs are the reader's to contain; this target checks that what comes
// back to the caller is only ever one of the two.
#include <array>

#include "fuzz/FuzzInput.h"
#include "mesh/SurfaceReader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tissuesim;
  if (size == 0) return 0;
  static constexpr std::array<const char*, 6> kExtensions = {".stl", ".obj",  ".ply",
                                                             ".off", ".gltf", ".glb"};
  const char* extension = kExtensions[data[0] % kExtensions.size()];
  const std::filesystem::path path = fuzz::asFile(data + 1, size - 1, extension);
  fuzz::expectOnlyOwnErrors<MeshFileError>([&] {
    const TriangleSurface surface = readSurface(path, {0.001, ""});
    if (!surface.vertices_m.allFinite()) std::abort();
    for (Eigen::Index f = 0; f < surface.triangleCount(); ++f) {
      for (int c = 0; c < 3; ++c) {
        if (surface.triangles(c, f) < 0 || surface.triangles(c, f) >= surface.vertexCount())
          std::abort();
      }
    }
  });
  std::filesystem::remove(path);
  return 0;
}
