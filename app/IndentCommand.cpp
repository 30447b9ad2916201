// SPDX-License-Identifier: Apache-2.0
#include "app/IndentCommand.h"

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "analysis/IndentationExperiment.h"
#include "app/CommandError.h"
#include "app/LoadedTissue.h"
#include "app/OutputFile.h"
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
};

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
    if (model != "springs" && model != "tets")
      throw CommandError("--models: unknown model '" + model + "'; expected springs or tets");
  }
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
      "through the FEM reference and spring networks of the given sizes; the probe's force at "
      "each depth and each network's error against the FEM (CSV; a table on stderr).");
  command->add_option("--tissue", options->tissuePath, "Tissue parameter file (JSON)")->required();
  command
      ->add_option("--models", options->models,
                   "Lattice models: springs (the simulator's network), tets (the tissue's "
                   "isochoric energy per tet, the volume term per cube)")
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
  command->add_option("--output", options->outputPath, "CSV file (default: stdout)");
  command->callback([options] { runIndent(*options); });
}

}  // namespace tissuesim::app
