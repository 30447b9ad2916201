// SPDX-License-Identifier: Apache-2.0
#pragma once
// `tissuesim uniaxial`: the cyclic uniaxial curve of one material point for one force law.

#include <CLI/CLI.hpp>

namespace tissuesim::app {

void registerUniaxialCommand(CLI::App& app);

}  // namespace tissuesim::app
