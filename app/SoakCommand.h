// SPDX-License-Identifier: Apache-2.0
#pragma once
// `tissuesim soak`: a long headless session of random pokes, grasps and releases (RandomSession),
// watched for what a long training session must never show: a non-finite or rolled-back step,
// energy growing without bound, memory creeping up. The physics rate over time is reported.

#include <CLI/CLI.hpp>

namespace tissuesim::app {

void registerSoakCommand(CLI::App& app);

}  // namespace tissuesim::app
