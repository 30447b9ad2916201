// SPDX-License-Identifier: Apache-2.0
#pragma once
// A uniaxial tensile test as an instructor brings it, read from CSV into the branches a fit
// works on (analysis/TissueFit.h). Three layouts, told apart by the header:
//
//   cycle,phase,lambda,stress_kpa     what `uniaxial` and `tensile` write: branches as listed
//   lambda,stress_kpa                 one sequence of stretch (1) and engineering stress (kPa)
//   displacement_mm,force_n           one sequence of the grips' displacement and the force,
//                                     with the specimen's gauge length and cross-section given
//
// A sequence is cut into branches where the stretch turns: rising runs load, falling runs
// unload, and each load after an unload starts a new cycle. Points are kept in the order
// measured (the Mullins memory depends on it). Stresses come out in Pa.

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <vector>

#include "analysis/UniaxialExperiment.h"

namespace tissuesim {

/// Bad test data; the message names the file, and the line or column, and what was expected.
class TestDataError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The specimen a displacement-force file was measured on (mm, mm^2, each > 0).
struct SpecimenGeometry {
  double gaugeLength_mm = 0.0;
  double crossSection_mm2 = 0.0;
};

/// @throws TestDataError: a missing or empty file, an unknown header, a value that is not a
/// finite number, a phase other than loading or unloading, a loading branch whose stretch falls
/// or an unloading one whose stretch rises, a stretch <= 0, a displacement file without its
/// specimen geometry.
std::vector<CurveBranch> readTensileTestCsv(const std::filesystem::path& path,
                                            const std::optional<SpecimenGeometry>& specimen = {});

}  // namespace tissuesim
