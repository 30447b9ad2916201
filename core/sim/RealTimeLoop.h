// SPDX-License-Identifier: Apache-2.0
#pragma once
// The fixed-rate loop: the Simulation stepped on its own thread at its time step (1 ms: the
// haptic rate), publishing a snapshot after every step for rendering, which reads it without
// ever blocking the physics (TripleBuffer). The instrument pose comes in the same way (a
// LiveInstrument the GUI or a device adapter writes).
//
// Pacing: step n is due at start + n dt (steady clock); a step done early sleeps until its
// successor is due. A step that finishes late is made up by the next steps running back to back
// while the loop is at most kMaxLagSteps periods behind (an occasional slow step: a new contact, a
// stall by the scheduler): simulated time stays on wall-clock time, so the tissue moves at the
// speed of the tool the trainee moves. Further behind than that, the lag is dropped (no spiral of
// death) and simulated time falls behind wall-clock time for good. Each late step is counted
// (overruns) and the measured real-time factor (simulated / wall seconds) says how much time was
// dropped. Nothing is dropped silently.

#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <thread>
#include <vector>

#include "sim/SessionRecording.h"
#include "sim/Simulation.h"
#include "sim/ToolProxy.h"
#include "sim/TripleBuffer.h"

namespace tissuesim {

/// What rendering needs of one physics step.
struct SimulationSnapshot {
  long step = 0;
  double time_s = 0.0;
  Eigen::Matrix3Xd positions_m;  ///< 3 by #V
  InstrumentPose instrument;
  Eigen::Vector3d toolForce_N = Eigen::Vector3d::Zero();
  double maxStretch = 1.0;
  /// The session's damaged springs (#S, 1 damaged: SessionAssessment::damagedSprings()).
  std::vector<std::uint8_t> damagedSprings;
  std::size_t eventCount = 0;  ///< instability events so far (the list stays with the physics)
  const char* latestEventKind = nullptr;  ///< Simulation::latestEventKind(): a literal or null
  /// Simulation::wantsRefinementTowardsTool(): the window makes the body again, paused.
  bool wantsRefinement = false;
};

/// An instrument pose written by one thread (the GUI, a device) and read by the physics.
/// With motion limits, the written pose is the target of a ToolProxy that the physics advances
/// by each step's time: the tool follows the input at bounded speed and acceleration.
class LiveInstrument final : public InstrumentSource {
 public:
  explicit LiveInstrument(const InstrumentPose& start) : m_poses(start) {}
  LiveInstrument(const InstrumentPose& start, ToolMotionLimits limits)
      : m_poses(start), m_proxy(std::in_place, start, limits) {}
  /// Input side (the GUI, a device): the newest pose, or the proxy's target.
  void setPose(const InstrumentPose& pose) {
    m_poses.back() = pose;
    m_poses.publish();
  }
  /// Physics side: the newest pose, or the proxy advanced to time_s (a time before the last,
  /// as after a reset, restarts its clock without moving it).
  InstrumentPose poseAt(double time_s) const override {
    m_poses.update();
    const long step = m_calls.fetch_add(1, std::memory_order_relaxed);
    if (m_recorder != nullptr) m_recorder->notePose(step, m_poses.front());
    if (!m_proxy) return m_poses.front();
    const double h_s = m_lastTime_s ? time_s - *m_lastTime_s : 0.0;
    m_lastTime_s = time_s;
    return m_proxy->advance(m_poses.front(), h_s, m_clearance_m);
  }
  /// Physics side: the clearance the proxy's next advance slows by, where it has a near speed.
  bool takesClearance() const override {
    return m_proxy && std::isfinite(m_proxy->limits().nearSpeed_m_s);
  }
  void noteClearance(double clearance_m) const override { m_clearance_m = clearance_m; }
  /// The proxy's speed limit near the organ (m/s; none without a proxy or a near limit: infinity).
  double nearSpeed_m_s() const {
    return m_proxy ? m_proxy->limits().nearSpeed_m_s : std::numeric_limits<double>::infinity();
  }
  /// A new speed limit near the organ for the proxy (ToolProxy::setNearSpeed; nothing without
  /// one). Physics side: from the stepping thread, or while no step runs.
  void setNearSpeed(double nearSpeed_m_s) {
    if (m_proxy) m_proxy->setNearSpeed(nearSpeed_m_s);
  }
  /// Steps that have asked for a pose so far: the session's clock for recordings.
  long steps() const { return m_calls.load(std::memory_order_relaxed); }
  /// Records each new input pose as the physics first sees it (null: none). Set while no loop
  /// runs; `recorder` must outlive this object or be unset.
  void setRecorder(SessionRecorder* recorder) { m_recorder = recorder; }

 private:
  mutable std::atomic<long> m_calls{0};
  SessionRecorder* m_recorder = nullptr;
  mutable TripleBuffer<InstrumentPose> m_poses;
  mutable std::optional<ToolProxy> m_proxy;
  mutable std::optional<double> m_lastTime_s;
  mutable double m_clearance_m = std::numeric_limits<double>::infinity();
};

struct LoopStatistics {
  long steps = 0;
  long overruns = 0;  ///< steps that finished after their due time
  double wall_s = 0.0;
  double simulated_s = 0.0;
  double realtimeFactor() const { return wall_s > 0.0 ? simulated_s / wall_s : 0.0; }
  double physicsHz() const { return wall_s > 0.0 ? static_cast<double>(steps) / wall_s : 0.0; }
};

class RealTimeLoop {
 public:
  /// The most periods the loop catches up after late steps (20 ms at 1 kHz). Why 20: with 4,
  /// every stall of the physics thread longer than 4 ms (a slow step run late, the scheduler,
  /// other processes on the machine) was lost for good, and the loop fell short of its rate
  /// (docs/performance.md has the figures). Made up, the tool and the tissue stay on wall-clock
  /// time; the steps that catch up run back to back, so a stall is made up within a few times
  /// its length. Further behind than that, time is dropped.
  static constexpr int kMaxLagSteps = 20;

  /// `simulation` must outlive the loop and is not touched by others while it runs.
  explicit RealTimeLoop(Simulation& simulation);
  ~RealTimeLoop();
  RealTimeLoop(const RealTimeLoop&) = delete;
  RealTimeLoop& operator=(const RealTimeLoop&) = delete;

  void start();
  void stop();
  /// Stepping now: started, and neither stopped nor ended by the before-step call.
  bool isRunning() const { return m_isRunning.load() && !m_hasEnded.load(); }
  /// Called on the physics thread before each step (a replay's recorded changes); returning
  /// false ends the loop before that step (the end of a replay), as stop() would. Set while the
  /// loop is stopped; it must not throw.
  void setBeforeStep(std::function<bool()> beforeStep) { m_beforeStep = std::move(beforeStep); }

  /// Reader side: refreshes to the newest snapshot if any; returns it.
  const SimulationSnapshot& snapshot() {
    m_snapshots.update();
    return m_snapshots.front();
  }
  LoopStatistics statistics() const;

 private:
  void run();

  Simulation& m_simulation;
  std::function<bool()> m_beforeStep;
  TripleBuffer<SimulationSnapshot> m_snapshots;
  std::thread m_thread;
  std::atomic<bool> m_isRunning{false};
  std::atomic<bool> m_shouldStop{false};
  std::atomic<bool> m_hasEnded{false};  ///< the before-step call ended the loop
  // Written by the physics thread once per step, read by anyone: atomics, so reading never
  // blocks the physics.
  std::atomic<long> m_steps{0};
  std::atomic<long> m_overruns{0};
  std::atomic<double> m_wall_s{0.0};
  std::atomic<double> m_simulated_s{0.0};
};

}  // namespace tissuesim
