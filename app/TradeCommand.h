// SPDX-License-Identifier: Apache-2.0
#pragma once
// `tissuesim trade`: the speed/accuracy map (app/trade/): every knob's cost on the bundled liver
// and its error against the FEM reference, written as CSV, Markdown and a PNG plot.

#include <CLI/CLI.hpp>

namespace tissuesim::app {

void registerTradeCommand(CLI::App& app);

}  // namespace tissuesim::app
