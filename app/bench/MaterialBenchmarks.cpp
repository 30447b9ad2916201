// SPDX-License-Identifier: Apache-2.0
#include "app/bench/MaterialBenchmarks.h"

#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "material/StiffnessTable.h"
#include "material/StrainEnergy.h"
#include "material/StressSoftening.h"
#include "material/TissueFile.h"

namespace tissuesim::app {
namespace {

/// The paper's liver mesh size (Section 4: 5,322 EESM elements).
constexpr int kPaperSpringCount = 5322;

/// Stretches a deforming liver's springs might show: within +-20 % of rest.
std::vector<double> sampleStretches(int count) {
  std::mt19937_64 random(42);
  std::uniform_real_distribution<double> stretch(0.8, 1.2);
  std::vector<double> values(static_cast<std::size_t>(count));
  for (double& value : values) value = stretch(random);
  return values;
}

}  // namespace

void registerMaterialBenchmarks(const std::string& tissuePath) {
  const TissueParameters parameters = loadTissueFile(tissuePath);

  benchmark::RegisterBenchmark("StiffnessTable/Build", [parameters](benchmark::State& state) {
    for (auto _ : state) {
      const StrainEnergy energy(parameters);
      const StiffnessTable table(energy);
      benchmark::DoNotOptimize(table.nodeCount());
    }
  })->Unit(benchmark::kMillisecond);

  const auto lookup = [parameters](benchmark::State& state, auto&& evaluate) {
    const StrainEnergy energy(parameters);
    const StiffnessTable table(energy);
    const StressSoftening softening(parameters);
    const std::vector<double> stretches = sampleStretches(kPaperSpringCount);
    for (auto _ : state) {
      double sum = 0.0;
      for (const double lambda : stretches) sum += evaluate(energy, table, softening, lambda);
      benchmark::DoNotOptimize(sum);
    }
    state.SetItemsProcessed(state.iterations() * kPaperSpringCount);
  };

  benchmark::RegisterBenchmark("StiffnessTable/StressLookup", [lookup](benchmark::State& state) {
    lookup(state, [](const StrainEnergy&, const StiffnessTable& table, const StressSoftening&,
                     double lambda) { return table.stress(lambda); });
  });
  benchmark::RegisterBenchmark(
      "StiffnessTable/StressAndSlopeLookup", [lookup](benchmark::State& state) {
        lookup(state, [](const StrainEnergy&, const StiffnessTable& table, const StressSoftening&,
                         double lambda) { return table.stressAndSlope(lambda).slope; });
      });
  benchmark::RegisterBenchmark("StiffnessTable/SoftenedStressLookup",
                               [lookup](benchmark::State& state) {
                                 lookup(state, [](const StrainEnergy&, const StiffnessTable& table,
                                                  const StressSoftening& softening, double lambda) {
                                   return softening.soften(table.stress(lambda), lambda, 1.25);
                                 });
                               });
  benchmark::RegisterBenchmark("StrainEnergy/ClosedFormStress", [lookup](benchmark::State& state) {
    lookup(state, [](const StrainEnergy& energy, const StiffnessTable&, const StressSoftening&,
                     double lambda) { return energy.stress(lambda); });
  });
}

}  // namespace tissuesim::app
