// SPDX-License-Identifier: Apache-2.0
// The scene file's parser: any bytes give a scene or a SceneFileError.
#include "fuzz/FuzzInput.h"
#include "sim/SceneFile.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tissuesim;
  const std::filesystem::path path = fuzz::asFile(data, size, ".json");
  fuzz::expectOnlyOwnErrors<SceneFileError>([&] { loadSceneFile(path); });
  return 0;
}
