// SPDX-License-Identifier: Apache-2.0
#pragma once
// A fixed set of worker threads that run one task split into parts, for the physics loop's
// per-spring and per-node passes. run(parts, task) calls task(part) once for every part in
// [0, parts) and returns when all have finished.
//
// Parts are claimed, not assigned: the caller and each awake worker take the next unclaimed
// part until none is left, and the caller waits only for parts that were claimed. A worker
// that the operating system has descheduled (two physics threads beside a busy renderer on two
// cores) therefore takes nothing, and the caller runs its share instead of waiting for it: with
// a fixed thread-to-part assignment such a run waited a whole scheduler slice (the step took
// three times as long on two threads as on one). Which thread runs a part never changes what the
// part computes, so callers that write per-part buffers stay bit-identical for any thread count.
//
// Why not std::async or a task queue: a 5,000-spring force pass takes ~0.2 ms, so a handoff has
// to cost microseconds and never allocate. Workers spin briefly after each task (the next one
// comes within a physics step) and then sleep on an atomic wait, so an idle simulation does
// not burn a core. Nothing here allocates after construction.

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace tissuesim {

class ForkJoinPool {
 public:
  /// The most parts one run may have.
  static constexpr int kMaxParts = 4095;

  /// @param threadCount total threads including the caller's, >= 1 (1: run() is a plain loop).
  explicit ForkJoinPool(int threadCount);
  ~ForkJoinPool();
  ForkJoinPool(const ForkJoinPool&) = delete;
  ForkJoinPool& operator=(const ForkJoinPool&) = delete;

  int threadCount() const { return static_cast<int>(m_workers.size()) + 1; }

  /// Runs task(part) once for each part in [0, parts) (1 <= parts <= kMaxParts), on whichever
  /// threads claim them, the caller's included; returns when all have returned. The task must
  /// not throw, and must not call run() on the same pool.
  template <typename Task>
  void run(int parts, const Task& task) {
    runErased(
        parts, [](const void* context, int part) { (*static_cast<const Task*>(context))(part); },
        &task);
  }

 private:
  using Function = void (*)(const void*, int);
  void runErased(int parts, Function function, const void* context);
  /// Claims and runs parts of run `job` until none is left or another run has begun.
  void runClaimedParts(std::uint64_t job);
  void workerLoop();

  // The claim word: job number (bits 24 and up), part count (bits 12-23), next part (bits 0-11).
  static constexpr int kCountShift = 12;
  static constexpr int kJobShift = 24;
  static constexpr std::uint64_t kFieldMask = (std::uint64_t{1} << kCountShift) - 1;

  std::vector<std::thread> m_workers;
  std::atomic<std::uint64_t> m_epoch{0};  ///< the current job number; workers wait on it
  std::atomic<std::uint64_t> m_claim{0};  ///< see above; parts are claimed by incrementing it
  std::atomic<int> m_done{0};             ///< parts of the current job that have returned
  std::atomic<bool> m_isStopping{false};
  Function m_function = nullptr;  ///< written before m_claim is published (release)
  const void* m_context = nullptr;
};

/// Runs task(part) for each part in [0, parts): on `pool` when there is one (a one-thread pool
/// runs them in order on the caller), else in order on the caller. What the passes that may or
/// may not have a pool call.
template <typename Task>
void runParts(ForkJoinPool* pool, int parts, const Task& task) {
  if (pool != nullptr) {
    pool->run(parts, task);
    return;
  }
  for (int part = 0; part < parts; ++part) task(part);
}

}  // namespace tissuesim
