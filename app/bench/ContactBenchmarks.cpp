#include "bench/ContactBenchmarks.h"

#include <memory>

#include <benchmark/benchmark.h>

#include "CapsuleContact.h"
#include "sim/SceneFile.h"
#include "sim/Simulation.h"

namespace tissuesim::app {

InstrumentPose pressedPose(const Simulation& simulation) {
  Eigen::Index top = 0;
  simulation.state().x.row(1).maxCoeff(&top);
  return {simulation.state().x.col(top) - Eigen::Vector3d(0, 0.005, 0), {0, -1, 0}, false};
}

void registerContactBenchmarks(const std::string& scenePath) {
  const SceneDescription scene = loadSceneFile(scenePath);
  benchmark::RegisterBenchmark("Contact/QueryAndResponse/liver5k", [scene](benchmark::State& state) {
    Simulation simulation(scene);
    CapsuleContact contact(simulation.geometry().mesh, {scene.instrument->shaftRadius_m, scene.instrument->shaftLength_m});
    const InstrumentPose pose = pressedPose(simulation);
    Eigen::Matrix3Xd forces = Eigen::Matrix3Xd::Zero(3, simulation.state().x.cols());
    PenaltyContactSet contacts;
    for (auto _ : state) {
      contacts.clear();
      contact.findContacts(simulation.state().x, pose, contacts);
      contacts.addForces(simulation.state().x, forces);
      benchmark::DoNotOptimize(forces.data());
    }
    state.counters["contacts"] = static_cast<double>(contacts.contacts().size());
    state.counters["boundary_triangles"] = static_cast<double>(contact.boundaryTriangleCount());
  })->Unit(benchmark::kMicrosecond);

  benchmark::RegisterBenchmark("Contact/WholeStep/liver5k", [scene](benchmark::State& state) {
    Simulation simulation(scene);
    CapsuleContact contact(simulation.geometry().mesh, {scene.instrument->shaftRadius_m, scene.instrument->shaftLength_m});
    InstrumentScript hold({{0.0, pressedPose(simulation)}});
    simulation.setContactProvider(&contact);
    simulation.setInstrumentSource(&hold);
    for (auto _ : state) benchmark::DoNotOptimize(simulation.step().contact.toolForce_N);
    state.counters["springs"] = static_cast<double>(simulation.springMesh().springCount());
    state.counters["steps_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  })->Unit(benchmark::kMicrosecond);
}

}  // namespace tissuesim::app
