// SPDX-License-Identifier: Apache-2.0
#pragma once
// `tissuesim run`: a headless session of a scene, with a scripted instrument, and a JSON report.

#include <CLI/CLI.hpp>

namespace tissuesim::app {

void registerRunCommand(CLI::App& app);

}  // namespace tissuesim::app
