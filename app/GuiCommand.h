// SPDX-License-Identifier: Apache-2.0
#pragma once
// The window: `tissuesim` with no arguments, or `tissuesim gui [--scene FILE]`.

#include <string>

#include <CLI/CLI.hpp>

namespace tissuesim::app {

/// Opens the window on a scene (and plays `recordingPath` when not empty) and runs Qt's event
/// loop; returns its exit code.
/// @throws CommandError when there is no X display to open it on (with what to do instead).
int runGui(const std::string& scenePath, const std::string& recordingPath, int argc, char** argv);

void registerGuiCommand(CLI::App& app, int argc, char** argv);

}  // namespace tissuesim::app
