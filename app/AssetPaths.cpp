// SPDX-License-Identifier: Apache-2.0
#include "app/AssetPaths.h"

namespace tissuesim::app {

std::filesystem::path bundledAsset(const std::string& relative) {
  const std::filesystem::path local = std::filesystem::path("assets") / relative;
  std::error_code error;
  if (std::filesystem::exists(local, error)) return local;
  return std::filesystem::path(TISSUESIM_SOURCE_DIR) / "assets" / relative;
}

}  // namespace tissuesim::app
