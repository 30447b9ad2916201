// SPDX-License-Identifier: Apache-2.0
#pragma once
// `tissuesim tensile`: the virtual tensile test of a meshed block specimen through the spring
// network, cycle after cycle, against the continuum curve.

#include <CLI/CLI.hpp>

namespace tissuesim::app {

void registerTensileCommand(CLI::App& app);

}  // namespace tissuesim::app
