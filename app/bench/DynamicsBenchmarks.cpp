// SPDX-License-Identifier: Apache-2.0
#include "app/bench/DynamicsBenchmarks.h"

#include <map>
#include <memory>
#include <string>
#include <tuple>

#include <benchmark/benchmark.h>

#include "integrators/ImplicitEulerSolver.h"
#include "integrators/QuasiNewtonSolver.h"
#include "integrators/SymplecticEulerSolver.h"
#include "material/TissueFile.h"
#include "mesh/BlockMesher.h"
#include "parallel/ForkJoinPool.h"
#include "springs/SpringMesh.h"

namespace tissuesim::app {
namespace {

/// A liver-sized slab held at its base, sagging under gravity: each benchmark iteration is one
/// physics step of the running simulation.
struct BenchScene {
  TissueParameters parameters;
  StrainEnergy energy;
  StiffnessTable table;
  SpringMesh mesh;
  SpringForceLaw law;
  SpringForceField springs;
  MechanicalSystem system;
  MechanicalState state;

  BenchScene(const TissueParameters& p, const Eigen::Vector3i& cells)
      : parameters(p),
        energy(parameters),
        table(energy),
        mesh(buildSpringMesh(makeBlockMesh({0.2, 0.2, 0.2 * cells.z() / cells.x()}, cells),
                             parameters.density_kg_m3)),
        law(SpringLaw::Eesm, table, parameters, 0.0, true),
        springs(mesh, law),
        system(springs, nullptr),
        state(system.restState()) {
    system.gravity.acceleration_m_s2 = {0.0, 0.0, -9.81};
    for (Eigen::Index i = 0; i < mesh.nodeCount(); ++i) {
      if (mesh.restPositions_m(2, i) < 1e-12) system.fixNode(static_cast<int>(i));
    }
  }
};

// (9, 9, 8) cells: 5,237 springs; (24, 24, 24): 102,024 springs.
const Eigen::Vector3i kPaperSize(9, 9, 8);
const Eigen::Vector3i kLargeSize(24, 24, 24);

/// Steps each step benchmark times, from the slab at rest. A fixed count, not a minimum time:
/// the slab sags and stiffens as it runs, so the work per step (CG products, explicit
/// substeps) depends on how far it has got: with a minimum time the 100k implicit step took 8
/// CG products a step in a short run and 22 in a two-second one. Each count is chosen so that a
/// benchmark steps for about a second (docs/performance.md).
int timedSteps(const Eigen::Vector3i& cells, bool isImplicit) {
  if (cells == kLargeSize) return isImplicit ? 30 : 20;
  return isImplicit ? 300 : 200;
}

void runSteps(benchmark::State& state, BenchScene& scene, TimeIntegrator& integrator, double dt) {
  int substeps = 0;
  int iterations = 0;
  long linearIterations = 0;
  for (auto _ : state) {
    const StepReport report = integrator.step(scene.system, scene.state, dt);
    substeps += report.substeps;
    iterations += report.iterations;
    linearIterations += report.linearIterations;
    if (report.refused || !report.isFinite) {
      state.SkipWithError(report.reason.c_str());
      break;
    }
  }
  const auto springs = static_cast<double>(scene.mesh.springCount());
  state.counters["springs"] = springs;
  state.counters["dt_ms"] = dt * 1e3;
  state.counters["steps_per_s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["substeps"] =
      static_cast<double>(substeps) / static_cast<double>(state.iterations());
  // The explicit integrator's own step is the substep (at its stable step size): its rate is
  // what compares with the explicit target; the slab stiffens as it sags, so the substeps per
  // benchmark step grow with the time simulated.
  state.counters["substeps_per_s"] =
      benchmark::Counter(static_cast<double>(substeps), benchmark::Counter::kIsRate);
  state.counters["iterations"] =
      static_cast<double>(iterations) / static_cast<double>(state.iterations());
  state.counters["cg_iterations"] =
      static_cast<double>(linearIterations) / static_cast<double>(state.iterations());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * springs));
}

/// The trade rows' implicit Euler: `iterations` Newton iterations, CG to `tolerance`.
ImplicitEulerSolver tradeIntegrator(int iterations, double tolerance) {
  IntegratorSettings settings;
  settings.massDamping_1_s = 1.0;
  settings.maxIterations = iterations;
  settings.linearTolerance = tolerance;
  settings.forceTolerance_N = 1e-9;
  return ImplicitEulerSolver(settings, LinearSolverKind::ConjugateGradient);
}

/// Steps from rest before a trade row's error is measured.
constexpr int kTradeSteps = 50;

/// The positions of a fully converged run (Newton to 30 iterations, CG 1e-10) after kTradeSteps
/// steps from rest, computed once per slab size and shared by every setting and thread count
/// (runs are bit-identical for any thread count): at 100k springs it is most of the trade rows'
/// set-up, and it was computed again for each of the eight rows.
const Eigen::Matrix3Xd& convergedTradeReference(const TissueParameters& parameters,
                                                const Eigen::Vector3i& cells, ForkJoinPool& pool) {
  static std::map<std::tuple<int, int, int>, Eigen::Matrix3Xd> references;
  const auto key = std::make_tuple(cells.x(), cells.y(), cells.z());
  auto found = references.find(key);
  if (found == references.end()) {
    BenchScene reference(parameters, cells);
    reference.springs.setThreadPool(&pool);
    ImplicitEulerSolver converged = tradeIntegrator(30, 1e-10);
    for (int n = 0; n < kTradeSteps; ++n) converged.step(reference.system, reference.state, 1e-3);
    found = references.emplace(key, reference.state.x).first;
  }
  return found->second;
}

/// Speed against accuracy: implicit Euler (CG) with a budget of Newton iterations and a CG
/// tolerance, timed, and its positions after 50 steps compared with a fully converged run from
/// the same start (error_um: the largest node difference, micrometres; moved_um: the converged
/// run's largest displacement from rest, for scale). On the paper's size (one thread: the names
/// without a suffix) and at 100k springs (one and two threads).
void registerAccuracyTrade(const TissueParameters& parameters, const Eigen::Vector3i& cells,
                           const std::string& suffix, int threads) {
  struct Setting {
    const char* name;
    int iterations;
    double linearTolerance;
  };
  for (const Setting setting : {Setting{"Trade/ImplicitCG/newton1_cg1e-2", 1, 1e-2},
                                Setting{"Trade/ImplicitCG/newton1_cg1e-4", 1, 1e-4},
                                Setting{"Trade/ImplicitCG/newton2_cg1e-6", 2, 1e-6},
                                Setting{"Trade/ImplicitCG/newton8_cg1e-8", 8, 1e-8}}) {
    benchmark::RegisterBenchmark(
        (setting.name + suffix).c_str(),
        [parameters, cells, threads, setting](benchmark::State& state) {
          ForkJoinPool pool(threads);
          const Eigen::Matrix3Xd& reference = convergedTradeReference(parameters, cells, pool);
          BenchScene scene(parameters, cells);
          scene.springs.setThreadPool(&pool);
          ImplicitEulerSolver timed = tradeIntegrator(setting.iterations, setting.linearTolerance);
          for (int n = 0; n < kTradeSteps; ++n) timed.step(scene.system, scene.state, 1e-3);
          const double error = (scene.state.x - reference).cwiseAbs().maxCoeff();
          const double moved = (reference - scene.mesh.restPositions_m).colwise().norm().maxCoeff();
          runSteps(state, scene, timed, 1e-3);
          state.counters["error_um"] = error * 1e6;
          state.counters["moved_um"] = moved * 1e6;
          state.counters["threads"] = threads;
        })
        ->Unit(benchmark::kMicrosecond)
        ->Iterations(timedSteps(cells, true));
  }
}

}  // namespace

void registerDynamicsBenchmarks(const std::string& tissuePath) {
  const TissueParameters parameters = loadTissueFile(tissuePath);
  registerAccuracyTrade(parameters, kPaperSize, "", 1);
  registerAccuracyTrade(parameters, kLargeSize, "/100k/threads:1", 1);
  registerAccuracyTrade(parameters, kLargeSize, "/100k/threads:2", 2);

  for (const auto& [label, cells] : {std::pair{"5k", kPaperSize}, std::pair{"100k", kLargeSize}}) {
    const std::string suffix = std::string("/") + label;
    benchmark::RegisterBenchmark(("SpringMesh/Build" + suffix).c_str(),
                                 [parameters, cells = cells](benchmark::State& state) {
                                   for (auto _ : state) {
                                     const SpringMesh mesh =
                                         buildSpringMesh(makeBlockMesh({0.2, 0.2, 0.2}, cells),
                                                         parameters.density_kg_m3);
                                     benchmark::DoNotOptimize(mesh.springCount());
                                   }
                                 })
        ->Unit(benchmark::kMillisecond);

    for (const int threads : {1, 2}) {
      const std::string threadSuffix = suffix + "/threads:" + std::to_string(threads);
      benchmark::RegisterBenchmark(("Step/Explicit" + threadSuffix).c_str(),
                                   [parameters, cells = cells, threads](benchmark::State& state) {
                                     BenchScene scene(parameters, cells);
                                     ForkJoinPool pool(threads);
                                     scene.springs.setThreadPool(&pool);
                                     IntegratorSettings settings;
                                     settings.massDamping_1_s = 1.0;
                                     SymplecticEulerSolver integrator(settings);
                                     // The largest step it takes without substepping.
                                     const double dt = SymplecticEulerSolver::stableTimeStep(
                                         scene.system, scene.state.x, settings.stabilitySafety);
                                     runSteps(state, scene, integrator, 0.99 * dt);
                                     state.counters["threads"] = threads;
                                   })
          ->Unit(benchmark::kMicrosecond)
          ->Iterations(timedSteps(cells, false));

      for (const auto& [name, kind] :
           {std::pair{"Step/ImplicitCG", LinearSolverKind::ConjugateGradient},
            std::pair{"Step/ImplicitCholesky", LinearSolverKind::Cholesky}}) {
        // Eigen's simplicial (non-supernodal) Cholesky takes 0.2 s a factorisation at 5k springs;
        // at 100k it would take minutes a step, so it is not run there.
        if (kind == LinearSolverKind::Cholesky && cells == kLargeSize) continue;
        if (kind == LinearSolverKind::Cholesky && threads > 1)
          continue;  // the factorisation is serial
        benchmark::RegisterBenchmark(
            (name + threadSuffix).c_str(),
            [parameters, cells = cells, kind = kind, threads](benchmark::State& state) {
              BenchScene scene(parameters, cells);
              ForkJoinPool pool(threads);
              scene.springs.setThreadPool(&pool);
              IntegratorSettings settings;
              settings.massDamping_1_s = 1.0;
              settings.maxIterations = 2;
              settings.forceTolerance_N = 1e-6;
              ImplicitEulerSolver integrator(settings, kind);
              runSteps(state, scene, integrator, 1e-3);
              state.counters["threads"] = threads;
            })
            ->Unit(benchmark::kMicrosecond)
            // Cholesky: 0.1 s a step, so ten of them.
            ->Iterations(kind == LinearSolverKind::Cholesky ? 10 : timedSteps(cells, true));
      }
    }

    if (cells == kLargeSize) continue;  // its prefactored H0 is a Cholesky too: see above
    benchmark::RegisterBenchmark(("Step/QuasiNewton" + suffix).c_str(),
                                 [parameters, cells = cells](benchmark::State& state) {
                                   BenchScene scene(parameters, cells);
                                   IntegratorSettings settings;
                                   settings.massDamping_1_s = 1.0;
                                   settings.maxIterations = 5;
                                   settings.forceTolerance_N = 1e-6;
                                   QuasiNewtonSolver integrator(settings);
                                   runSteps(state, scene, integrator, 1e-3);
                                 })
        ->Unit(benchmark::kMicrosecond)
        ->Iterations(timedSteps(cells, true) / 3);  // about 5 ms a step
  }
}

}  // namespace tissuesim::app
