// SPDX-License-Identifier: Apache-2.0
// tissuesim: the one executable. Subcommands do the work; each has --help.

#include <exception>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "app/AssetPaths.h"
#include "app/BenchCommand.h"
#include "app/CommandError.h"
#include "app/FitCommand.h"
#include "app/GuiCommand.h"
#include "app/IndentCommand.h"
#include "app/LargeBlocksReturned.h"
#include "app/MeshCommand.h"
#include "app/OrganPokeCommand.h"
#include "app/ReplayCommand.h"
#include "app/RunCommand.h"
#include "app/SnapshotCommand.h"
#include "app/SoakCommand.h"
#include "app/TensileCommand.h"
#include "app/TradeCommand.h"
#include "app/UniaxialCommand.h"

int main(int argc, char** argv) {
  tissuesim::app::returnLargeBlocksToTheSystem();
  CLI::App app{
      "TissueSim: real-time soft-tissue simulation with the Equivalent Energy Spring "
      "Model (Moreno-Guerra et al., Polymers 2022)",
      "tissuesim"};
  app.set_version_flag("--version", "tissuesim 0.1.0");
  app.require_subcommand(0, 1);
  // One line on error, as for every other failure of the program.
  app.failure_message([](const CLI::App*, const CLI::Error& error) {
    return std::string("tissuesim: error: ") + error.what() + " (see --help)\n";
  });
  tissuesim::app::registerUniaxialCommand(app);
  tissuesim::app::registerTensileCommand(app);
  tissuesim::app::registerFitCommand(app);
  tissuesim::app::registerIndentCommand(app);
  tissuesim::app::registerOrganPokeCommand(app);
  tissuesim::app::registerTradeCommand(app);
  tissuesim::app::registerMeshCommand(app);
  tissuesim::app::registerRunCommand(app);
  tissuesim::app::registerReplayCommand(app);
  tissuesim::app::registerSnapshotCommand(app);
  tissuesim::app::registerSoakCommand(app);
  tissuesim::app::registerBenchCommand(app);
  tissuesim::app::registerGuiCommand(app, argc, argv);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  } catch (const std::exception& error) {
    std::cerr << "tissuesim: error: " << error.what() << "\n";
    return 1;
  }
  if (app.get_subcommands().empty()) {
    // No subcommand: the trainee's window on the bundled liver scene.
    try {
      return tissuesim::app::runGui(tissuesim::app::bundledAsset("scenes/liver-poke.json").string(),
                                    "", 1, argv);
    } catch (const std::exception& error) {
      std::cerr << "tissuesim: error: " << error.what() << "\n";
      return 1;
    }
  }
  return 0;
}
