// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <CLI/CLI.hpp>

namespace tissuesim::app {

/// `tissuesim snapshot`: a scene stepped headless for N frames, rendered offscreen to a PNG.
void registerSnapshotCommand(CLI::App& app);

}  // namespace tissuesim::app
