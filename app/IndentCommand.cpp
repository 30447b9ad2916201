// SPDX-License-Identifier: Apache-2.0
#include "app/IndentCommand.h"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "analysis/IndentationExperiment.h"
#include "analysis/IndentationHapticRate.h"
#include "app/CommandError.h"
#include "app/LoadedTissue.h"
#include "app/OutputFile.h"
#include "app/Percentile.h"
#include "fem/FemModel.h"

namespace tissuesim::app {
namespace {

struct IndentCommandOptions {
  std::string tissuePath;
  std::vector<double> depths_mm{2.0, 4.0};
  int refinement = 1;
  std::vector<int> springs{1000, 5300};
  double volumeTerm_kPa = 0.0;
  std::vector<std::string> models{"springs"};
  std::string outputPath;
  // The fem-haptic-rate model's body, its contact and its clock (organ-poke's options alike).
  double hapticRateFinest_mm = IndentationBodyGrading{}.finest_m * 1000.0;
  double hapticRateGrowth = IndentationBodyGrading{}.growth;
  double hapticRateCoarsest_mm = IndentationBodyGrading{}.coarsest_m * 1000.0;
  double hapticRateSpacing_mm = 1.0;
  int hapticRateIterations = HapticRateSettings{}.newtonIterations;
  double hapticRateVolumeTerm_kPa = 0.0;  ///< 0: the reference's bulk modulus
  double speed_mm_s = 2.0;
  double updateLatency_ms = 0.0;  ///< 0: each update's wall time
};

/// The fem-haptic-rate row: the probe's force at each depth, its timings on stderr.
IndentationCurve indentAtHapticRate(const IndentCommandOptions& options, const LoadedTissue& tissue,
                                    const IndentationSetup& setup) {
  IndentationBodyGrading grading;
  grading.finest_m = options.hapticRateFinest_mm / 1000.0;
  grading.growth = options.hapticRateGrowth;
  grading.coarsest_m = options.hapticRateCoarsest_mm / 1000.0;
  HapticRateSettings settings;
  settings.speed_m_s = options.speed_mm_s / 1000.0;
  settings.updateLatency_s = options.updateLatency_ms / 1000.0;
  settings.newtonIterations = options.hapticRateIterations;
  const double bulkModulus_Pa = options.hapticRateVolumeTerm_kPa > 0.0
                                    ? 1000.0 * options.hapticRateVolumeTerm_kPa
                                    : defaultFemBulkModulus(tissue.energy);
  HapticRatePoke poke;
  try {
    poke = indentHapticRate(tissue.energy, setup, grading, bulkModulus_Pa,
                            options.hapticRateSpacing_mm / 1000.0, settings);
  } catch (const std::invalid_argument& error) {
    throw CommandError(std::string("fem-haptic-rate: ") + error.what());
  }
  const auto quantile = [&](double share) { return percentile(poke.stepTimes_ms, share); };
  const double meanUpdate_ms = poke.updates > 0 ? 1e3 * poke.updating_s / poke.updates : 0.0;
  char latency[64] = "its own wall time";
  if (options.updateLatency_ms > 0.0)
    std::snprintf(latency, sizeof latency, "%g ms", options.updateLatency_ms);
  std::fprintf(stderr,
               "fem-haptic-rate: %ld contact steps at %.3g ms median, %.3g ms p99, %ld unsettled; "
               "%ld FEM updates at %.0f ms mean, %.0f ms longest, each used %s after it started\n",
               poke.steps, quantile(0.5), quantile(0.99), poke.unconvergedSteps, poke.updates,
               meanUpdate_ms, 1e3 * poke.longestUpdate_s, latency);
  IndentationCurve curve;
  curve.force_N = poke.force_N;
  curve.nodes = poke.nodes;
  curve.elements = poke.elements;
  curve.seconds = poke.seconds;
  return curve;
}

void runIndent(const IndentCommandOptions& options) {
  if (options.refinement < 1 || options.refinement > 8)
    throw CommandError("--refinement " + std::to_string(options.refinement) +
                       " is out of range; expected 1 to 8");
  for (const int count : options.springs) {
    if (count < 100 || count > 200000)
      throw CommandError("--springs " + std::to_string(count) +
                         " is out of range; expected 100 to 200000");
  }
  if (options.volumeTerm_kPa < 0.0) throw CommandError("--volume-term-kpa must be >= 0");
  for (const std::string& model : options.models) {
    if (model != "springs" && model != "tets" && model != "fem-haptic-rate")
      throw CommandError("--models: unknown model '" + model +
                         "'; expected springs, tets or fem-haptic-rate");
  }
  if (!(options.speed_mm_s > 0.0)) throw CommandError("--speed-mm-s must be > 0");
  if (options.updateLatency_ms < 0.0) throw CommandError("--update-latency-ms must be >= 0");
  if (options.hapticRateIterations < 1 || options.hapticRateIterations > 20)
    throw CommandError("--haptic-rate-iterations must be 1 to 20");
  if (options.hapticRateVolumeTerm_kPa < 0.0)
    throw CommandError("--haptic-rate-volume-term-kpa must be >= 0");
  if (!(options.hapticRateSpacing_mm >= 0.1) || options.hapticRateSpacing_mm > 5.0)
    throw CommandError("--haptic-rate-spacing-mm must be 0.1 to 5");
  if (!(options.hapticRateFinest_mm >= 0.5) || options.hapticRateFinest_mm > 15.0)
    throw CommandError("--haptic-rate-finest-mm must be 0.5 to 15");
  if (!(options.hapticRateGrowth >= 0.3) || options.hapticRateGrowth > 10.0)
    throw CommandError("--haptic-rate-growth must be 0.3 to 10");
  if (!(options.hapticRateCoarsest_mm >= options.hapticRateFinest_mm) ||
      options.hapticRateCoarsest_mm > 30.0)
    throw CommandError("--haptic-rate-coarsest-mm must be from --haptic-rate-finest-mm to 30");
  IndentationSetup setup;
  setup.depths_m = indentationDepthsFromMm(options.depths_mm);
  if (!options.outputPath.empty()) checkOutputWritable(options.outputPath, "--output");
  const LoadedTissue tissue(options.tissuePath);

  std::fprintf(stderr,
               "indent: %.0f x %.0f x %.0f mm block, bottom held, a %.1f mm probe at the top "
               "centre\n",
               setup.size_m.x() * 1e3, setup.size_m.y() * 1e3, setup.size_m.z() * 1e3,
               setup.probeRadius_m * 1e3);
  struct Row {
    std::string model;
    IndentationCurve curve;
  };
  std::vector<Row> rows;
  rows.push_back(
      {"fem (refinement " + std::to_string(options.refinement) + ")",
       indentFem(tissue.energy, setup, options.refinement, defaultFemBulkModulus(tissue.energy))});
  for (const std::string& model : options.models) {
    if (model == "fem-haptic-rate") {
      rows.push_back({model, indentAtHapticRate(options, tissue, setup)});
      continue;
    }
    for (const int count : options.springs) {
      IndentationNetwork network{indentationCellEdge(setup, count), SpringLaw::Eesm,
                                 options.volumeTerm_kPa * 1000.0};
      std::string name = model + " ~" + std::to_string(count);  // the lattice's springs
      if (model == "tets") {
        // The isochoric tets' volumetric part: the FEM reference's bulk modulus, or the one
        // asked for.
        network.model = LatticeModel::IsochoricTets;
        if (!(network.bulkModulus_Pa > 0.0))
          network.bulkModulus_Pa = defaultFemBulkModulus(tissue.energy);
      } else if (options.volumeTerm_kPa > 0.0) {
        name += " + volume";
      }
      rows.push_back({name, indentSprings(tissue.energy, tissue.table, setup, network)});
    }
  }
  std::string csv = "model,nodes,elements,depth_mm,force_n,error_vs_fem_percent,seconds\n";
  const std::vector<double>& reference = rows.front().curve.force_N;
  for (const Row& row : rows) {
    std::fprintf(stderr, "%-28s %6d nodes %7d elements %6.1f s", row.model.c_str(), row.curve.nodes,
                 row.curve.elements, row.curve.seconds);
    for (std::size_t d = 0; d < setup.depths_m.size(); ++d) {
      const double error = 100.0 * (row.curve.force_N[d] / reference[d] - 1.0);
      std::fprintf(stderr, "  %.1f mm: %.3f N (%+.0f %%)", options.depths_mm[d],
                   row.curve.force_N[d], error);
      char line[256];
      std::snprintf(line, sizeof line, "%s,%d,%d,%.6g,%.6g,%.3f,%.3f\n", row.model.c_str(),
                    row.curve.nodes, row.curve.elements, options.depths_mm[d], row.curve.force_N[d],
                    error, row.curve.seconds);
      csv += line;
    }
    if (row.curve.unconvergedPoints > 0) {
      std::fprintf(stderr, "  [%d solves stopped at %.1e N]", row.curve.unconvergedPoints,
                   row.curve.worstResidual_N);
    }
    std::fprintf(stderr, "\n");
  }
  if (options.outputPath.empty()) {
    std::fputs(csv.c_str(), stdout);
  } else {
    writeTextFile(options.outputPath, "--output", csv);
  }
}

}  // namespace

std::vector<double> indentationDepthsFromMm(const std::vector<double>& depths_mm) {
  std::vector<double> depths_m;
  double last = 0.0;
  for (const double depth : depths_mm) {
    // Past about 4.5 mm the continuum under the 2.5 mm probe reaches the chains' locking
    // stretch: the FEM has no equilibrium there (docs/performance.md).
    if (!(depth > last) || depth > 4.5)
      throw CommandError("--depths-mm must increase, each in (0, 4.5] mm");
    depths_m.push_back(depth / 1000.0);
    last = depth;
  }
  return depths_m;
}

void registerIndentCommand(CLI::App& app) {
  auto options = std::make_shared<IndentCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "indent",
      "Indentation test: a 60 x 60 x 30 mm block pressed at its centre by the instrument's probe, "
      "through the FEM reference and the --models (spring networks of the given sizes, the FEM "
      "at its own rate); the probe's force at each depth and each model's error against the "
      "FEM (CSV; a table on stderr).");
  command->add_option("--tissue", options->tissuePath, "Tissue parameter file (JSON)")->required();
  command
      ->add_option("--models", options->models,
                   "Models: springs (the simulator's network), tets (the tissue's isochoric "
                   "energy per tet, the volume term per cube), both on lattices of --springs "
                   "sizes; fem-haptic-rate (the reference's element at its own rate, the "
                   "probe's contact at each 1 ms step, the probe moving at --speed-mm-s, on "
                   "the whole block refined towards the probe by the --haptic-rate-* options)")
      ->delimiter(',')
      ->capture_default_str();
  command->add_option("--depths-mm", options->depths_mm, "Depths below the top face, increasing")
      ->delimiter(',')
      ->capture_default_str();
  command
      ->add_option("--refinement", options->refinement,
                   "FEM: cells of probe radius / refinement at the probe (1-8)")
      ->capture_default_str();
  command->add_option("--springs", options->springs, "Spring networks of about these sizes")
      ->delimiter(',')
      ->capture_default_str();
  command
      ->add_option("--volume-term-kpa", options->volumeTerm_kPa,
                   "The networks' volume term (0: none)")
      ->capture_default_str();
  command
      ->add_option("--haptic-rate-finest-mm", options->hapticRateFinest_mm,
                   "fem-haptic-rate: the body's edges at the probe (mm), as a scene's "
                   "tet_mesh.refine_towards_tool.finest_mm")
      ->capture_default_str();
  command
      ->add_option("--haptic-rate-growth", options->hapticRateGrowth,
                   "fem-haptic-rate: their growth away from the probe (mm per mm)")
      ->capture_default_str();
  command
      ->add_option("--haptic-rate-coarsest-mm", options->hapticRateCoarsest_mm,
                   "fem-haptic-rate: the coarse block's cubes, refined towards the probe (mm)")
      ->capture_default_str();
  command
      ->add_option("--haptic-rate-spacing-mm", options->hapticRateSpacing_mm,
                   "fem-haptic-rate: the probe's contact points this far apart (mm)")
      ->capture_default_str();
  command
      ->add_option("--haptic-rate-iterations", options->hapticRateIterations,
                   "fem-haptic-rate: Newton iterations an FEM update")
      ->capture_default_str();
  command
      ->add_option("--haptic-rate-volume-term-kpa", options->hapticRateVolumeTerm_kPa,
                   "fem-haptic-rate: its bulk modulus (kPa; 0: the reference's)")
      ->capture_default_str();
  command->add_option("--speed-mm-s", options->speed_mm_s, "fem-haptic-rate: the probe's speed")
      ->capture_default_str();
  command
      ->add_option("--update-latency-ms", options->updateLatency_ms,
                   "fem-haptic-rate: each FEM update used this long after it starts (0: when "
                   "done, its own wall time)")
      ->capture_default_str();
  command->add_option("--output", options->outputPath, "CSV file (default: stdout)");
  command->callback([options] { runIndent(*options); });
}

}  // namespace tissuesim::app
