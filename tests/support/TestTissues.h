// SPDX-License-Identifier: Apache-2.0
#pragma once
// Shared fixtures: the bundled porcine liver and paths to test data.

#include <string>

#include "material/TissueFile.h"

namespace tissuesim::test {

inline std::string tissueDataPath(const std::string& name) {
  return std::string(TISSUESIM_TEST_DATA_DIR) + "/tissues/" + name;
}

/// The paper's porcine liver (assets/tissues/porcine-liver.json).
inline TissueParameters porcineLiver() {
  return loadTissueFile(std::string(TISSUESIM_ASSET_DIR) + "/tissues/porcine-liver.json");
}

}  // namespace tissuesim::test
