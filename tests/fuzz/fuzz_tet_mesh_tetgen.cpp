// SPDX-License-Identifier: Apache-2.0
// The TetGen reader: the input is split at its first NUL byte into the .node and the .ele file;
// any bytes give a mesh or a MeshFileError.
#include <algorithm>

#include "fuzz/FuzzInput.h"
#include "mesh/TetMeshFile.h"
#include "mesh/TriangleSurface.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tissuesim;
  const std::uint8_t* split = std::find(data, data + size, std::uint8_t{0});
  const std::filesystem::path node =
      fuzz::asFile(data, static_cast<std::size_t>(split - data), ".node");
  const std::uint8_t* rest = split == data + size ? split : split + 1;
  // The same name as the .node's, so the reader finds it beside that one.
  fuzz::asFile(rest, static_cast<std::size_t>(data + size - rest), ".ele");
  fuzz::expectOnlyOwnErrors<MeshFileError>([&] { readTetMesh(node); });
  return 0;
}
