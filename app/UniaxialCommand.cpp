#include "UniaxialCommand.h"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "CommandError.h"
#include "analysis/GoodnessOfFit.h"
#include "analysis/UniaxialTest.h"
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
};

void writeCsv(std::ostream& out, const std::vector<CurveBranch>& branches) {
  constexpr double kPaPerKpa = 1000.0;
  out << "cycle,phase,lambda,stress_kpa\n";
  char line[128];
  for (const CurveBranch& branch : branches) {
    for (std::size_t i = 0; i < branch.stretch.size(); ++i) {
      std::snprintf(line, sizeof line, "%d,%s,%.9g,%.9g\n", branch.cycle, phaseName(branch.phase),
                    branch.stretch[i], branch.stress_Pa[i] / kPaPerKpa);
      out << line;
    }
  }
}

void runUniaxial(const UniaxialOptions& options) {
  const auto model = parseUniaxialModel(options.modelName);
  if (!model) {
    throw CommandError("unknown --model '" + options.modelName + "'; expected one of " +
                       modelNames());
  }
  const TissueParameters parameters = loadTissueFile(options.tissuePath);
  const StrainEnergy energy(parameters);
  const StiffnessTable table(energy);
  const UniaxialTest test(energy, table);
  const UniaxialProtocol protocol{options.lambdaMax, options.points};
  try {
    test.validate(protocol);
  } catch (const std::invalid_argument& error) {
    throw CommandError(std::string(error.what()) + " (tissue " + options.tissuePath + ")");
  }

  const std::vector<CurveBranch> curve = test.run(*model, protocol);
  const std::vector<CurveBranch> reference = test.run(UniaxialModel::Sedf, protocol);

  if (options.outputPath.empty()) {
    writeCsv(std::cout, curve);
  } else {
    std::ofstream out(options.outputPath);
    if (!out) throw CommandError("cannot write --output " + options.outputPath);
    writeCsv(out, curve);
    if (!out.flush()) throw CommandError("failed writing --output " + options.outputPath);
  }

  std::fprintf(stderr, "tissue: %s; model: %s; locking at lambda = %.4f, usable up to %.4f\n",
               parameters.name.c_str(), options.modelName.c_str(), energy.lockingRange().upper,
               table.range().upper);
  if (*model == UniaxialModel::Smm) {
    std::fprintf(stderr, "smm: fitted modulus E = %.6g kPa (stress = E (lambda - 1))\n",
                 UniaxialTest::fitLinearModulus(reference) / 1000.0);
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
  command->add_option("--tissue", options->tissuePath, "Tissue parameter file (JSON)")
      ->required();
  command->add_option("--model", options->modelName, "Force law: " + modelNames())->required();
  command->add_option("--lambda-max", options->lambdaMax,
                      "Peak stretch of each cycle, comma-separated (e.g. 1.15,1.23,1.30)")
      ->required()
      ->delimiter(',');
  command->add_option("--points", options->points, "Points per branch (>= 2)")
      ->capture_default_str();
  command->add_option("--output", options->outputPath, "CSV file (default: stdout)");
  command->callback([options] { runUniaxial(*options); });
}

}  // namespace tissuesim::app
