// SPDX-License-Identifier: Apache-2.0
#pragma once
// `--plot FILE.png` of `uniaxial` and `tensile`: the stress-stretch curves of the models run,
// one line each through all their cycles, with the `sedf` reference dashed, rendered with VTK's
// charts offscreen (a private Xvfb when there is no display).

#include <string>
#include <utility>
#include <vector>

#include "analysis/UniaxialExperiment.h"

namespace tissuesim::app {

/// Renders and writes the chart (900 x 600). Callers check the path first, before the work
/// (checkPngOutput). @throws CommandError when it cannot be written.
void writeCurvePlot(const std::string& path, const std::string& title,
                    const std::vector<std::pair<std::string, std::vector<CurveBranch>>>& models,
                    const std::vector<CurveBranch>& reference,
                    const std::string& referenceName = "sedf (reference)");

}  // namespace tissuesim::app
