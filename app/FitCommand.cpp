// SPDX-License-Identifier: Apache-2.0
#include "app/FitCommand.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/SecondsSince.h"
#include "analysis/TensileTestData.h"
#include "analysis/TissueFit.h"
#include "app/AssetPaths.h"
#include "app/CommandError.h"
#include "app/CurvePlot.h"
#include "app/ImageSize.h"
#include "app/OutputFile.h"
#include "material/TissueFile.h"

namespace tissuesim::app {
namespace {

struct FitOptions {
  std::string dataPath;
  std::string outputPath;
  std::string plotPath;
  std::vector<std::string> fixed;  ///< NAME=VALUE
  std::string name;
  std::string startPath;
  double length_mm = 0.0;
  double area_mm2 = 0.0;
  int starts = 12;
};

void runFit(const FitOptions& options) {
  checkOutputWritable(options.outputPath, "--output");
  if (!options.plotPath.empty()) checkPngOutput(options.plotPath, "--plot");
  if (options.starts < 1) throw CommandError("--starts must be at least 1");
  std::optional<SpecimenGeometry> specimen;
  if (options.length_mm != 0.0 || options.area_mm2 != 0.0) {
    if (!(options.length_mm > 0.0) || !(options.area_mm2 > 0.0)) {
      throw CommandError("--length-mm and --area-mm2 must both be given, each > 0");
    }
    specimen = SpecimenGeometry{options.length_mm, options.area_mm2};
  }
  std::vector<CurveBranch> data;
  try {
    data = readTensileTestCsv(options.dataPath, specimen);
  } catch (const TestDataError& error) {
    throw CommandError(error.what());
  }

  // The tissue the first start of each stage begins from, and that gives what the fit keeps
  // (density, v_ij, n, f): the one given, or the bundled porcine liver.
  TissueFitOptions fit;
  try {
    fit.base = loadTissueFile(options.startPath.empty() ? bundledAsset("tissues/porcine-liver.json")
                                                        : std::filesystem::path(options.startPath));
  } catch (const TissueFileError& error) {
    throw CommandError(error.what());
  }
  fit.base.name = "fitted tissue";
  if (specimen) fit.base.springArea_m2 = specimen->crossSection_mm2 * 1e-6;
  // --fix NAME=VALUE: the value, in the file's unit, goes into the base before the fit.
  for (const std::string& item : options.fixed) {
    const auto equals = item.find('=');
    if (equals == std::string::npos) {
      throw CommandError("--fix '" + item + "': expected NAME=VALUE, e.g. mu_kpa=0.1");
    }
    const std::string name = item.substr(0, equals);
    const std::string text = item.substr(equals + 1);
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value)) {
      throw CommandError("--fix " + name + ": '" + text + "' is not a number");
    }
    try {
      setFitParameter(fit.base, name, value);
    } catch (const std::invalid_argument& error) {
      throw CommandError("--fix " + name + ": " + error.what());
    }
    fit.fixed.push_back(name);
  }
  fit.starts = options.starts;
  const auto started = std::chrono::steady_clock::now();
  bool isShowingProgress = false;  // only for a fit that takes more than a second
  fit.progress = [&](int done, int total) {
    const double seconds = secondsSince(started);
    isShowingProgress = isShowingProgress || seconds > 1.0;
    if (isShowingProgress) {
      std::fprintf(stderr, "\rfitting: start %d of %d (%.1f s)%s", done, total, seconds,
                   done == total ? "\n" : "");
    }
  };

  TissueFitResult result;
  try {
    result = fitTissue(data, fit);
  } catch (const std::invalid_argument& error) {
    throw CommandError(options.dataPath + ": " + error.what());
  }
  TissueParameters& fitted = result.parameters;
  fitted.name = options.name.empty() ? fit.base.name : options.name;
  std::size_t points = 0;
  for (const CurveBranch& branch : data) points += branch.stretch.size();
  fitted.source =
      "fitted by tissuesim fit to " + options.dataPath + " (" + std::to_string(points) + " points)";
  const std::string text = tissueFileText(fitted, fitSummary(result));
  try {
    parseTissueJson(text, options.outputPath);  // what the simulator will read back
  } catch (const TissueFileError& error) {
    throw CommandError(std::string("the fitted tissue is not admissible: ") + error.what());
  }
  writeTextFile(options.outputPath, "--output", text);

  std::printf("%-8s %14s %14s\n", "", "value", "std. error");
  for (const FittedParameter& entry : result.table) {
    if (entry.isFixed) {
      std::printf("%-8s %14.6g %14s\n", entry.name.c_str(), entry.value, "(held)");
    } else {
      std::printf("%-8s %14.6g %14.3g%s\n", entry.name.c_str(), entry.value, entry.uncertainty,
                  entry.isIdentified ? "" : "  not identified");
    }
  }
  for (const BranchFit& branch : result.branches) {
    std::printf("cycle %d %-9s R^2 = %.6f\n", branch.cycle, phaseName(branch.phase),
                branch.rSquared);
  }
  for (const std::string& note : result.notes) std::printf("note: %s\n", note.c_str());
  for (const std::string& warning : result.warnings) std::printf("warning: %s\n", warning.c_str());
  std::printf("wrote %s\n", options.outputPath.c_str());

  if (!options.plotPath.empty()) {
    std::vector<CurveBranch> model = data;
    for (std::size_t b = 0; b < model.size(); ++b) model[b].stress_Pa = result.branches[b].model_Pa;
    writeCurvePlot(options.plotPath, fitted.name + ": the fit over the test data", {{"fit", model}},
                   data, "test data");
  }
}

}  // namespace

void registerFitCommand(CLI::App& app) {
  auto options = std::make_shared<FitOptions>();
  CLI::App* command = app.add_subcommand(
      "fit",
      "Fit a tissue file to a uniaxial loading and unloading test: mu, N, f, A1, A2 on the "
      "loading branches, then b and C on the unloading ones; R^2 per branch and each constant's "
      "standard error on stdout.");
  command
      ->add_option("--data", options->dataPath,
                   "CSV: cycle,phase,lambda,stress_kpa (as uniaxial writes), lambda,stress_kpa, "
                   "or displacement_mm,force_n (with --length-mm and --area-mm2)")
      ->required();
  command->add_option("--output", options->outputPath, "The fitted tissue file (JSON)")->required();
  command->add_option("--plot", options->plotPath, "Also draw the fit over the data to this PNG");
  command
      ->add_option("--fix", options->fixed,
                   "Hold parameters at given values, comma-separated NAME=VALUE (file units: "
                   "e.g. mu_kpa=0.1,N=1.2)")
      ->delimiter(',');
  command->add_option("--name", options->name, "The fitted tissue's name");
  command->add_option("--start", options->startPath,
                      "A tissue file to start from and to take density and v_ij from (default: "
                      "the paper's porcine liver)");
  command->add_option("--length-mm", options->length_mm, "Specimen gauge length (mm)");
  command->add_option("--area-mm2", options->area_mm2, "Specimen cross-section (mm^2)");
  command->add_option("--starts", options->starts, "Starting points per stage (>= 1)")
      ->capture_default_str();
  command->callback([options] { runFit(*options); });
}

}  // namespace tissuesim::app
