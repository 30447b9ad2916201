#include "parallel/ForkJoinPool.h"

#include <stdexcept>
#include <string>

namespace tissuesim {
namespace {
/// How long a thread polls before it sleeps: a few tens of microseconds, about the gap
/// between two force passes of one physics step.
constexpr int kSpinCount = 2000;

inline void relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}
}  // namespace

ForkJoinPool::ForkJoinPool(int threadCount) {
  if (threadCount < 1) {
    throw std::invalid_argument("ForkJoinPool: thread count " + std::to_string(threadCount) +
                                " (expected at least 1)");
  }
  m_workers.reserve(static_cast<std::size_t>(threadCount - 1));
  for (int part = 1; part < threadCount; ++part) {
    m_workers.emplace_back([this, part] { workerLoop(part); });
  }
}

ForkJoinPool::~ForkJoinPool() {
  m_isStopping.store(true, std::memory_order_relaxed);
  m_epoch.fetch_add(1, std::memory_order_release);
  m_epoch.notify_all();
  for (std::thread& worker : m_workers) worker.join();
}

void ForkJoinPool::runErased(Function function, void* context) {
  if (m_workers.empty()) {
    function(context, 0);
    return;
  }
  m_function = function;
  m_context = context;
  m_pending.store(static_cast<int>(m_workers.size()), std::memory_order_relaxed);
  m_epoch.fetch_add(1, std::memory_order_release);
  m_epoch.notify_all();
  function(context, 0);
  for (int spin = 0; spin < kSpinCount; ++spin) {
    if (m_pending.load(std::memory_order_acquire) == 0) return;
    relax();
  }
  for (int pending = m_pending.load(std::memory_order_acquire); pending != 0;
       pending = m_pending.load(std::memory_order_acquire)) {
    m_pending.wait(pending, std::memory_order_acquire);
  }
}

void ForkJoinPool::workerLoop(int part) {
  std::uint64_t seen = 0;
  for (;;) {
    std::uint64_t epoch = m_epoch.load(std::memory_order_acquire);
    for (int spin = 0; spin < kSpinCount && epoch == seen; ++spin) {
      relax();
      epoch = m_epoch.load(std::memory_order_acquire);
    }
    while (epoch == seen) {
      m_epoch.wait(seen, std::memory_order_acquire);
      epoch = m_epoch.load(std::memory_order_acquire);
    }
    seen = epoch;
    if (m_isStopping.load(std::memory_order_relaxed)) return;
    m_function(m_context, part);
    if (m_pending.fetch_sub(1, std::memory_order_acq_rel) == 1) m_pending.notify_one();
  }
}

}  // namespace tissuesim
