// SPDX-License-Identifier: Apache-2.0
#include "app/TensileCommand.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/FemTensileExperiment.h"
#include "analysis/GoodnessOfFit.h"
#include "analysis/NetworkCalibration.h"
#include "analysis/SecondsSince.h"
#include "analysis/TensileExperiment.h"
#include "app/CommandError.h"
#include "app/CurveCsv.h"
#include "app/CurvePlot.h"
#include "app/ImageSize.h"
#include "app/LoadedTissue.h"
#include "app/OutputFile.h"
#include "fem/FemModel.h"
#include "material/TissueFile.h"

namespace tissuesim::app {
namespace {

struct TensileCommandOptions {
  std::string tissuePath;
  std::string modelName = "eesm";
  std::vector<double> lambdaMax;
  std::string size = "55x20x5";
  int resolution = 2;
  std::string integrator = "static";
  int points = 25;
  std::string outputPath;
  std::string plotPath;
  std::string calibration = "simulator";
  double bulkModulus_kPa = 0.0;
  bool isSofteningOff = false;
  bool isComparing = false;
};

Eigen::Vector3d parseSize(const std::string& text) {
  Eigen::Vector3d size_mm;
  char x1 = 0;
  char x2 = 0;
  std::istringstream in(text);
  in >> size_mm.x() >> x1 >> size_mm.y() >> x2 >> size_mm.z();
  if (!in || x1 != 'x' || x2 != 'x' || !in.eof() || !(size_mm.array() > 0.0).all() ||
      !size_mm.allFinite()) {
    throw CommandError("--size '" + text +
                       "': expected LENGTHxWIDTHxTHICKNESS in mm, e.g. 55x20x5");
  }
  return size_mm / 1000.0;
}

SpringLaw parseLaw(const std::string& name) {
  if (const std::optional<SpringLaw> law = springLawNamed(name)) return *law;
  throw CommandError("unknown --model '" + name +
                     "'; expected one of eesm, eesm-paper, smm (spring laws), tets or fem");
}

/// Runs `experiment` (which returns a curve), timing it into `seconds`; what it refuses
/// (std::invalid_argument) becomes the command's one-line error.
template <typename Experiment>
std::vector<CurveBranch> timedCurve(const Experiment& experiment, double& seconds) {
  const auto start = std::chrono::steady_clock::now();
  try {
    std::vector<CurveBranch> curve = experiment();
    seconds = secondsSince(start);
    return curve;
  } catch (const std::invalid_argument& error) {
    throw CommandError(error.what());
  }
}

/// The bulk modulus a continuum model (fem, tets) runs with: the one given, else the FEM's.
double continuumBulkModulus(const TensileCommandOptions& options, const LoadedTissue& tissue) {
  return options.bulkModulus_kPa > 0.0 ? options.bulkModulus_kPa * 1000.0
                                       : defaultFemBulkModulus(tissue.energy);
}

/// A hyperelastic model's run reported: its loading branches against sedf's virgin curve at the
/// same stretches (it has no softening, so sedf's softened branches are not what it stands for)
/// and `summary` (its solve's figures) on stderr, then the curve's CSV and plot.
void reportHyperelasticRun(const TensileCommandOptions& options, const LoadedTissue& tissue,
                           const char* model, std::vector<CurveBranch> curve,
                           const std::vector<CurveBranch>& reference, const char* summary) {
  std::fprintf(stderr, "%-11s %-28s %12s\n", "model", "branch", "R^2 virgin");
  for (std::size_t b = 0; b < curve.size(); b += 2) {
    std::vector<double> virgin;
    for (const double lambda : curve[b].stretch) virgin.push_back(tissue.energy.stress(lambda));
    char branch[64];
    std::snprintf(branch, sizeof branch, "cycle %d (lambda_max %.3f)", curve[b].cycle,
                  options.lambdaMax[static_cast<std::size_t>(curve[b].cycle - 1)]);
    std::fprintf(stderr, "%-11s %-28s %11.4f%%\n", model, branch,
                 100.0 * coefficientOfDetermination(virgin, curve[b].stress_Pa));
  }
  std::fprintf(stderr, "%-11s %s\n", model, summary);
  writeCurveCsv(options.outputPath, curve);
  if (!options.plotPath.empty()) {
    std::vector<std::pair<std::string, std::vector<CurveBranch>>> plotted;
    plotted.emplace_back(model, std::move(curve));
    writeCurvePlot(options.plotPath, tissue.parameters.name + ": tensile test", plotted, reference);
  }
}

/// The FEM reference (fem/FemModel.h) through the same specimen and protocol: hyperelastic, so
/// its loading branches are compared with sedf's and its unloading ones are not.
void runFemTensile(const TensileCommandOptions& options, const LoadedTissue& tissue,
                   const UniaxialProtocol& protocol, const std::vector<CurveBranch>& reference) {
  const TensileSpecimen specimen{parseSize(options.size), options.resolution};
  const double bulkModulus_Pa = continuumBulkModulus(options, tissue);
  std::fprintf(stderr,
               "tensile: %.4g x %.4g x %.4g mm, %d cells across the thickness, FEM (quadratic "
               "tets, mean dilatation), bulk modulus %.4g kPa, no softening\n",
               specimen.size_m.x() * 1e3, specimen.size_m.y() * 1e3, specimen.size_m.z() * 1e3,
               specimen.cellsAcrossThickness, bulkModulus_Pa / 1000.0);
  FemTensileStats stats;
  double seconds = 0.0;
  std::vector<CurveBranch> curve = timedCurve(
      [&] { return runFemTensileTest(tissue.energy, specimen, bulkModulus_Pa, protocol, &stats); },
      seconds);
  char summary[256];
  std::snprintf(summary, sizeof summary,
                "%d nodes, %d quadratic tets; max |net force| %.2g N (worst %d iterations), %d "
                "unconverged points; volume ratio %.5f to %.5f; %.2f s",
                stats.nodes, stats.elements, stats.worstResidual_N, stats.worstIterations,
                stats.unconvergedPoints, stats.minVolumeRatio, stats.maxVolumeRatio, seconds);
  reportHyperelasticRun(options, tissue, "fem", std::move(curve), reference, summary);
}

/// The lattice FEM (a scene's effects.model fem: the isochoric energy in each of the lattice's
/// linear tets, the volume term per cube its volumetric part) through the springs' specimen.
void runTetsTensile(const TensileCommandOptions& options, const LoadedTissue& tissue,
                    const UniaxialProtocol& protocol, const std::vector<CurveBranch>& reference) {
  const TensileSpecimen specimen{parseSize(options.size), options.resolution};
  TensileOptions run;
  run.model = LatticeModel::IsochoricTets;
  run.bulkModulus_Pa = continuumBulkModulus(options, tissue);
  std::fprintf(stderr,
               "tensile: %.4g x %.4g x %.4g mm, %d cells across the thickness, FEM on the "
               "lattice (linear tets, the volume term per cube), bulk modulus %.4g kPa, no "
               "softening\n",
               specimen.size_m.x() * 1e3, specimen.size_m.y() * 1e3, specimen.size_m.z() * 1e3,
               specimen.cellsAcrossThickness, run.bulkModulus_Pa / 1000.0);
  TensilePointStats stats;
  double seconds = 0.0;
  std::vector<CurveBranch> curve = timedCurve(
      [&] {
        return TensileExperiment(tissue.energy, tissue.table, specimen).run(run, protocol, &stats);
      },
      seconds);
  char summary[256];
  std::snprintf(summary, sizeof summary,
                "%d nodes, %d tets; max |net force| %.2g N, %.2g per N of grip force (worst %d "
                "iterations), %d unconverged points; %.2f s",
                stats.nodes, stats.tets, stats.worstResidual_N, stats.worstRelativeResidual,
                stats.worstIterations, stats.unconvergedPoints, seconds);
  reportHyperelasticRun(options, tissue, "tets", std::move(curve), reference, summary);
}

void runTensile(const TensileCommandOptions& options) {
  const bool isFem = options.modelName == "fem";
  const bool isTets = options.modelName == "tets";
  const SpringLaw law = isFem || isTets ? SpringLaw::Eesm : parseLaw(options.modelName);
  if (options.calibration != "simulator" && options.calibration != "small-strain" &&
      options.calibration != "with-volume" && options.calibration != "none") {
    throw CommandError("unknown --calibration '" + options.calibration +
                       "'; expected simulator, small-strain, with-volume or none");
  }
  if (options.resolution < 1 || options.resolution > 40) {
    throw CommandError("--resolution " + std::to_string(options.resolution) +
                       " is out of range; expected 1 to 40 cells across the thickness");
  }
  if (options.bulkModulus_kPa < 0.0) throw CommandError("--bulk-modulus-kpa must be >= 0");
  const std::string& integrator = options.integrator;
  if (integrator != "static" && integrator != "implicit" && integrator != "quasi-newton" &&
      integrator != "explicit") {
    throw CommandError("unknown --integrator '" + integrator +
                       "'; expected static, implicit, quasi-newton or explicit");
  }
  if (!options.outputPath.empty()) checkOutputWritable(options.outputPath, "--output");
  if (!options.plotPath.empty()) checkPngOutput(options.plotPath, "--plot");
  const LoadedTissue tissue(options.tissuePath);
  const StrainEnergy& energy = tissue.energy;
  const StiffnessTable& table = tissue.table;
  const UniaxialProtocol protocol{options.lambdaMax, options.points};
  tissue.validate(protocol);
  const std::vector<CurveBranch> reference = tissue.continuum.run(UniaxialModel::Sedf, protocol);
  if (isFem || isTets) {
    const std::string model = "--model " + options.modelName;
    if (options.isComparing) throw CommandError("--compare is for the spring laws, not " + model);
    if (integrator != "static") throw CommandError(model + " runs static equilibria only");
    if (options.calibration != "simulator")
      throw CommandError("--calibration is for the spring laws, not " + model);
    if (isFem) {
      runFemTensile(options, tissue, protocol, reference);
    } else {
      runTetsTensile(options, tissue, protocol, reference);
    }
    return;
  }

  const TensileSpecimen specimen{parseSize(options.size), options.resolution};
  const TensileExperiment test(energy, table, specimen);
  const double bulkModulus_Pa = options.bulkModulus_kPa * 1000.0;
  const double calibration = options.calibration == "none" ? 1.0
                             : options.calibration == "simulator"
                                 ? simulatorStiffnessScale(energy, table, bulkModulus_Pa)
                                 : test.smallStrainCalibration(
                                       energy.initialShearModulus(),
                                       options.calibration == "with-volume" ? bulkModulus_Pa : 0.0);

  std::vector<SpringLaw> laws = {law};
  if (options.isComparing) {
    for (const SpringLaw other : {SpringLaw::Eesm, SpringLaw::EesmPaper, SpringLaw::Smm}) {
      if (other != law) laws.push_back(other);
    }
  }
  std::fprintf(stderr,
               "tensile: %.4g x %.4g x %.4g mm, %d cells across the thickness, integrator %s, "
               "calibration %s (V_e x %.4f)\n",
               specimen.size_m.x() * 1e3, specimen.size_m.y() * 1e3, specimen.size_m.z() * 1e3,
               specimen.cellsAcrossThickness, options.integrator.c_str(),
               options.calibration.c_str(), calibration);
  std::fprintf(stderr, "%-11s %-28s %10s %10s\n", "model", "branch", "R^2 load", "R^2 unload");
  std::vector<std::pair<std::string, std::vector<CurveBranch>>> plotted;
  for (const SpringLaw each : laws) {
    TensileOptions run;
    run.law = each;
    run.isSoftening = !options.isSofteningOff;
    run.volumeScale = calibration;
    run.bulkModulus_Pa = options.bulkModulus_kPa * 1000.0;
    run.integrator = options.integrator;
    run.linearModulus_Pa = UniaxialExperiment::fitLinearModulus(reference);
    TensilePointStats stats;
    double seconds = 0.0;
    std::vector<CurveBranch> curve =
        timedCurve([&] { return test.run(run, protocol, &stats); }, seconds);
    const char* name = springLawName(each);
    for (std::size_t b = 0; b + 1 < curve.size(); b += 2) {
      char branch[64];
      std::snprintf(branch, sizeof branch, "cycle %d (lambda_max %.3f)", curve[b].cycle,
                    options.lambdaMax[static_cast<std::size_t>(curve[b].cycle - 1)]);
      std::fprintf(
          stderr, "%-11s %-28s %9.4f%% %9.4f%%\n", name, branch,
          100.0 * coefficientOfDetermination(reference[b].stress_Pa, curve[b].stress_Pa),
          100.0 * coefficientOfDetermination(reference[b + 1].stress_Pa, curve[b + 1].stress_Pa));
    }
    std::fprintf(stderr,
                 "%-11s %d nodes, %d springs; max |net force| %.2g N, %.2g per N of grip force "
                 "(worst %d iterations), %d unconverged points; %.2f s\n",
                 name, stats.nodes, stats.springs, stats.worstResidual_N,
                 stats.worstRelativeResidual, stats.worstIterations, stats.unconvergedPoints,
                 seconds);
    if (each == law) writeCurveCsv(options.outputPath, curve);
    plotted.emplace_back(std::string(name) + " (network)", std::move(curve));
  }
  if (!options.plotPath.empty()) {
    writeCurvePlot(options.plotPath, tissue.parameters.name + ": tensile test", plotted, reference);
  }
}

}  // namespace

void registerTensileCommand(CLI::App& app) {
  auto options = std::make_shared<TensileCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "tensile",
      "Virtual tensile test: a meshed block specimen pulled quasi-statically through the spring "
      "network to each lambda_max and back. CSV as `uniaxial`; R^2 against sedf on stderr.");
  command->add_option("--tissue", options->tissuePath, "Tissue parameter file (JSON)")->required();
  command
      ->add_option("--model", options->modelName,
                   "Spring law (eesm, eesm-paper, smm); tets: the FEM on the springs' lattice "
                   "(linear tets, the volume term per cube; a scene's effects.model fem); or fem: "
                   "the finite-element reference (quadratic tets, mean dilatation). tets and fem "
                   "are hyperelastic, with no softening")
      ->capture_default_str();
  command
      ->add_option("--lambda-max", options->lambdaMax,
                   "Peak stretch of each cycle, comma-separated (e.g. 1.15,1.23,1.30)")
      ->required()
      ->delimiter(',');
  command->add_option("--size", options->size, "Specimen LENGTHxWIDTHxTHICKNESS in mm")
      ->capture_default_str();
  command->add_option("--resolution", options->resolution, "Cells across the thickness (1-40)")
      ->capture_default_str();
  command
      ->add_option("--integrator", options->integrator,
                   "static (Newton on equilibrium), implicit, quasi-newton or explicit "
                   "(damped pseudo-time to the same tolerance)")
      ->capture_default_str();
  command->add_option("--points", options->points, "Points per branch (>= 2)")
      ->capture_default_str();
  command->add_option("--output", options->outputPath, "CSV file (default: stdout)");
  command->add_option("--plot", options->plotPath,
                      "Also draw the curves and the sedf reference to this PNG");
  command
      ->add_option("--calibration", options->calibration,
                   "simulator (what the simulator does: scale V_e so the springs' initial modulus "
                   "is 3 mu0, refitted to the continuum's loading over the paper's cycles when "
                   "there is a volume term), small-strain (the springs' factor alone), "
                   "with-volume (3 mu0 with the volume term in place) or none")
      ->capture_default_str();
  command
      ->add_option("--bulk-modulus-kpa", options->bulkModulus_kPa,
                   "Volume term's bulk modulus in kPa (0: off); with --model tets or fem, the "
                   "model's (0: the FEM's default, 200 times the tissue's stiffest tangent up to "
                   "lambda 1.3)")
      ->capture_default_str();
  command->add_flag("--no-softening", options->isSofteningOff, "Turn the Mullins effect off");
  command->add_flag("--compare", options->isComparing,
                    "Also run the other two spring laws and print their R^2 (CSV: --model only)");
  command->callback([options] { runTensile(*options); });
}

}  // namespace tissuesim::app
