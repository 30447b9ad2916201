// SPDX-License-Identifier: Apache-2.0
#pragma once
// `tissuesim replay`: a recorded session (`run --record`, the window's File > Save recording)
// stepped again headless, to the same bits: the same report, the same images.

#include <CLI/CLI.hpp>

namespace tissuesim::app {

void registerReplayCommand(CLI::App& app);

}  // namespace tissuesim::app
