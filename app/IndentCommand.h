// SPDX-License-Identifier: Apache-2.0
#pragma once
// `tissuesim indent`: the indentation test (core/analysis/IndentationTest.h) through the FEM
// reference and the spring network side by side: the probe's force at each depth, and each
// network's error against the FEM.

#include <CLI/CLI.hpp>

namespace tissuesim::app {

void registerIndentCommand(CLI::App& app);

}  // namespace tissuesim::app
