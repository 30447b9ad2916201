// SPDX-License-Identifier: Apache-2.0
#include "sim/RealTimeLoop.h"

#include <chrono>

namespace tissuesim {

namespace {
SimulationSnapshot initialSnapshot(const Simulation& simulation) {
  SimulationSnapshot snapshot;
  snapshot.step = simulation.steps();
  snapshot.time_s = simulation.time_s();
  snapshot.positions_m = simulation.state().x;
  snapshot.instrument = simulation.instrumentPose();
  snapshot.damagedSprings = simulation.assessment().damagedSprings();
  snapshot.eventCount = simulation.eventCount();
  snapshot.latestEventKind = simulation.latestEventKind();
  return snapshot;
}
}  // namespace

RealTimeLoop::RealTimeLoop(Simulation& simulation)
    : m_simulation(simulation), m_snapshots(initialSnapshot(simulation)) {}

RealTimeLoop::~RealTimeLoop() { stop(); }

void RealTimeLoop::start() {
  if (isRunning()) return;
  if (m_thread.joinable()) m_thread.join();  // ended by the before-step call
  m_hasEnded = false;
  m_shouldStop = false;
  m_isRunning = true;
  m_thread = std::thread([this] { run(); });
}

void RealTimeLoop::stop() {
  m_shouldStop = true;
  if (m_thread.joinable()) m_thread.join();
  m_isRunning = false;
  m_hasEnded = false;
}

LoopStatistics RealTimeLoop::statistics() const {
  LoopStatistics statistics;
  statistics.steps = m_steps.load();
  statistics.overruns = m_overruns.load();
  statistics.wall_s = m_wall_s.load();
  statistics.simulated_s = m_simulated_s.load();
  return statistics;
}

void RealTimeLoop::run() {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(m_simulation.timeStep_s()));
  // Simulated time is counted from here: the simulation may have run before this loop did
  // (a scripted approach, a paused and resumed window).
  const double startTime_s = m_simulation.time_s();
  auto due = start;
  long steps = 0;
  long overruns = 0;
  while (!m_shouldStop.load(std::memory_order_relaxed)) {
    if (m_beforeStep && !m_beforeStep()) {
      m_hasEnded = true;
      break;
    }
    const StepOutcome outcome = m_simulation.step();
    ++steps;
    SimulationSnapshot& snapshot = m_snapshots.back();
    snapshot.step = m_simulation.steps();
    snapshot.time_s = m_simulation.time_s();
    snapshot.positions_m = m_simulation.state().x;  // same size every step: no reallocation
    snapshot.instrument = m_simulation.instrumentPose();
    snapshot.toolForce_N = outcome.contact.toolForce_N;
    snapshot.maxStretch = outcome.maxStretch;
    snapshot.damagedSprings = m_simulation.assessment().damagedSprings();  // same size: a copy
    snapshot.eventCount = m_simulation.eventCount();
    snapshot.latestEventKind = m_simulation.latestEventKind();
    snapshot.wantsRefinement = m_simulation.wantsRefinementTowardsTool();
    m_snapshots.publish();

    due += period;
    const auto now = Clock::now();
    if (now > due) {
      ++overruns;
      // Behind: the next step starts now. Within kMaxLagSteps periods the schedule is kept (the
      // steps that follow catch up); beyond, the lag is dropped and the schedule restarts here.
      if (now - due > kMaxLagSteps * period) due = now;
    } else {
      std::this_thread::sleep_until(due);
    }
    m_steps.store(steps);
    m_overruns.store(overruns);
    m_wall_s.store(std::chrono::duration<double>(Clock::now() - start).count());
    m_simulated_s.store(m_simulation.time_s() - startTime_s);
  }
}

}  // namespace tissuesim
