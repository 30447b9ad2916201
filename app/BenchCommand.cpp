// SPDX-License-Identifier: Apache-2.0
#include "app/BenchCommand.h"

#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "app/AssetPaths.h"
#include "app/CommandError.h"
#include "app/bench/ContactBenchmarks.h"
#include "app/bench/DynamicsBenchmarks.h"
#include "app/bench/FemUpdateBenchmarks.h"
#include "app/bench/MaterialBenchmarks.h"
#include "app/bench/RenderBenchmarks.h"

namespace tissuesim::app {
namespace {

struct BenchOptions {
  std::string tissuePath;
  std::string scenePath;
  std::vector<std::string> benchmarkArguments;
};

void runBench(const BenchOptions& options) {
  registerMaterialBenchmarks(options.tissuePath);
  registerDynamicsBenchmarks(options.tissuePath);
  registerContactBenchmarks(options.scenePath);
  registerFemUpdateBenchmarks();
  registerRenderBenchmarks(options.scenePath);
  std::vector<std::string> arguments = {"tissuesim bench"};
  arguments.insert(arguments.end(), options.benchmarkArguments.begin(),
                   options.benchmarkArguments.end());
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  int argc = static_cast<int>(argv.size());
  benchmark::Initialize(&argc, argv.data());
  if (benchmark::ReportUnrecognizedArguments(argc, argv.data())) {
    throw CommandError("unrecognised benchmark argument (see tissuesim bench --help)");
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
}

}  // namespace

void registerBenchCommand(CLI::App& app) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* command = app.add_subcommand(
      "bench",
      "Run the Google Benchmark suite. Further arguments go to Google Benchmark, e.g. "
      "--benchmark_filter=Table --benchmark_min_time=0.05. Benchmarks report; they never fail.");
  options->tissuePath = bundledAsset("tissues/porcine-liver.json").string();
  command->add_option("--tissue", options->tissuePath, "Tissue parameter file (JSON)")
      ->capture_default_str();
  options->scenePath = bundledAsset("scenes/liver-poke.json").string();
  command->add_option("--scene", options->scenePath, "Scene for the contact benchmarks (JSON)")
      ->capture_default_str();
  command->allow_extras();
  command->callback([options, command] {
    options->benchmarkArguments = command->remaining();
    runBench(*options);
  });
}

}  // namespace tissuesim::app
