// SPDX-License-Identifier: Apache-2.0
#pragma once
// `tissuesim bench`: the Google Benchmark suite (speed targets live here, not in unit tests).

#include <CLI/CLI.hpp>

namespace tissuesim::app {

void registerBenchCommand(CLI::App& app);

}  // namespace tissuesim::app
