// SPDX-License-Identifier: Apache-2.0
#include "app/UniaxialCommand.h"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "analysis/GoodnessOfFit.h"
#include "analysis/UniaxialExperiment.h"
#include "app/CommandError.h"
#include "app/CurveCsv.h"
#include "app/CurvePlot.h"
#include "app/ImageSize.h"
#include "app/LoadedTissue.h"
#include "app/OutputFile.h"
#include "material/StiffnessTable.h"
#include "material/StrainEnergy.h"
#include "material/TissueFile.h"

namespace tissuesim::app {
namespace {

struct UniaxialOptions {
  std::string tissuePath;
  std::string modelName;
  std::vector<double> lambdaMax;
  int points = 100;
  std::string outputPath;
  std::string plotPath;
};

void runUniaxial(const UniaxialOptions& options) {
  const auto model = parseUniaxialModel(options.modelName);
  if (!model) {
    throw CommandError("unknown --model '" + options.modelName + "'; expected one of " +
                       modelNames());
  }
  if (!options.outputPath.empty()) checkOutputWritable(options.outputPath, "--output");
  if (!options.plotPath.empty()) checkPngOutput(options.plotPath, "--plot");
  const LoadedTissue tissue(options.tissuePath);
  const TissueParameters& parameters = tissue.parameters;
  const StrainEnergy& energy = tissue.energy;
  const StiffnessTable& table = tissue.table;
  const UniaxialExperiment& test = tissue.continuum;
  const UniaxialProtocol protocol{options.lambdaMax, options.points};
  tissue.validate(protocol);

  const std::vector<CurveBranch> curve = test.run(*model, protocol);
  const std::vector<CurveBranch> reference = test.run(UniaxialModel::Sedf, protocol);

  writeCurveCsv(options.outputPath, curve);
  if (!options.plotPath.empty()) {
    writeCurvePlot(options.plotPath, parameters.name + ": uniaxial, " + options.modelName,
                   {{options.modelName, curve}}, reference);
  }

  std::fprintf(stderr, "tissue: %s; model: %s; locking at lambda = %.4f, usable up to %.4f\n",
               parameters.name.c_str(), options.modelName.c_str(), energy.lockingRange().upper,
               table.range().upper);
  if (*model == UniaxialModel::Smm) {
    std::fprintf(stderr, "smm: fitted modulus E = %.6g kPa (stress = E (lambda - 1))\n",
                 UniaxialExperiment::fitLinearModulus(reference) / 1000.0);
  }
  for (std::size_t b = 0; b < curve.size(); ++b) {
    const double r2 = coefficientOfDetermination(reference[b].stress_Pa, curve[b].stress_Pa);
    std::fprintf(stderr, "cycle %d %-9s lambda_max %.4f: R^2 vs sedf = %.6f (%.4f %%)\n",
                 curve[b].cycle, phaseName(curve[b].phase),
                 options.lambdaMax[static_cast<std::size_t>(curve[b].cycle - 1)], r2, 100.0 * r2);
  }
}

}  // namespace

void registerUniaxialCommand(CLI::App& app) {
  auto options = std::make_shared<UniaxialOptions>();
  CLI::App* command = app.add_subcommand(
      "uniaxial",
      "Cyclic uniaxial test of one material point: loading to each lambda_max and unloading, "
      "stress softening carried between cycles. CSV on stdout or --output; R^2 against sedf on "
      "stderr.");
  command->add_option("--tissue", options->tissuePath, "Tissue parameter file (JSON)")->required();
  command->add_option("--model", options->modelName, "Force law: " + modelNames())->required();
  command
      ->add_option("--lambda-max", options->lambdaMax,
                   "Peak stretch of each cycle, comma-separated (e.g. 1.15,1.23,1.30)")
      ->required()
      ->delimiter(',');
  command->add_option("--points", options->points, "Points per branch (>= 2)")
      ->capture_default_str();
  command->add_option("--output", options->outputPath, "CSV file (default: stdout)");
  command->add_option("--plot", options->plotPath,
                      "Also draw the curves and the sedf reference to this PNG");
  command->callback([options] { runUniaxial(*options); });
}

}  // namespace tissuesim::app
