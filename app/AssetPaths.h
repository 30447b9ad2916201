// SPDX-License-Identifier: Apache-2.0
#pragma once
// Where the bundled assets are: ./assets when run from a checkout, else the source tree the
// program was built from.

#include <filesystem>
#include <string>

namespace tissuesim::app {

/// The path of a bundled asset, e.g. bundledAsset("tissues/porcine-liver.json").
std::filesystem::path bundledAsset(const std::string& relative);

}  // namespace tissuesim::app
