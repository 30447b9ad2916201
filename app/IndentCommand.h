// SPDX-License-Identifier: Apache-2.0
#pragma once
// `tissuesim indent`: the indentation test (core/analysis/IndentationExperiment.h) through the FEM
// reference and the spring network side by side: the probe's force at each depth, and each
// network's error against the FEM.

#include <vector>

#include <CLI/CLI.hpp>

namespace tissuesim::app {

void registerIndentCommand(CLI::App& app);

/// `--depths-mm` (as typed) checked and in metres: increasing, each in (0, 4.5] mm, for `indent`
/// and `trade`. @throws CommandError naming the option.
std::vector<double> indentationDepthsFromMm(const std::vector<double>& depths_mm);

}  // namespace tissuesim::app
