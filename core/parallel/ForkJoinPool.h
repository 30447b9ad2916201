#pragma once
// A fixed set of worker threads that run one task split into parts, for the physics loop's
// per-spring work. run(task) calls task(part) for part = 0 .. threadCount() - 1, part 0 on the
// calling thread, and returns when every part has finished.
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
  /// @param threadCount total threads including the caller's, >= 1 (1: run() is a plain call).
  explicit ForkJoinPool(int threadCount);
  ~ForkJoinPool();
  ForkJoinPool(const ForkJoinPool&) = delete;
  ForkJoinPool& operator=(const ForkJoinPool&) = delete;

  int threadCount() const { return static_cast<int>(m_workers.size()) + 1; }

  /// Runs task(part) for every part, in parallel; returns when all have returned. The task
  /// must not throw, and must not call run() on the same pool.
  template <typename Task>
  void run(Task& task) {
    runErased([](void* context, int part) { (*static_cast<Task*>(context))(part); }, &task);
  }

 private:
  using Function = void (*)(void*, int);
  void runErased(Function function, void* context);
  void workerLoop(int part);

  std::vector<std::thread> m_workers;
  std::atomic<std::uint64_t> m_epoch{0};  ///< bumped once per run(); workers wait on it
  std::atomic<int> m_pending{0};          ///< worker parts not yet finished in this run
  std::atomic<bool> m_isStopping{false};
  Function m_function = nullptr;  ///< written before m_epoch is bumped (release), read after
  void* m_context = nullptr;
};

}  // namespace tissuesim
