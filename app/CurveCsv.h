// SPDX-License-Identifier: Apache-2.0
#pragma once
// The CSV of a cyclic curve, shared by `uniaxial` and `tensile`:
// header `cycle,phase,lambda,stress_kpa`, one row per point, engineering stress in kPa.

#include <ostream>
#include <string>
#include <vector>

#include "analysis/UniaxialExperiment.h"

namespace tissuesim::app {

void writeCurveCsv(std::ostream& out, const std::vector<CurveBranch>& branches);

/// Writes to `path`, or to stdout when it is empty. @throws CommandError if it cannot.
void writeCurveCsv(const std::string& path, const std::vector<CurveBranch>& branches);

}  // namespace tissuesim::app
