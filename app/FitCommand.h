// SPDX-License-Identifier: Apache-2.0
#pragma once
// `tissuesim fit`: a tissue file fitted to a uniaxial loading and unloading test
// (analysis/TissueFit.h), with R^2 per branch and each constant's uncertainty.

#include <CLI/CLI.hpp>

namespace tissuesim::app {

void registerFitCommand(CLI::App& app);

}  // namespace tissuesim::app
