// SPDX-License-Identifier: Apache-2.0
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
  for (int worker = 1; worker < threadCount; ++worker) {
    m_workers.emplace_back([this] { workerLoop(); });
  }
}

ForkJoinPool::~ForkJoinPool() {
  m_isStopping.store(true, std::memory_order_relaxed);
  m_epoch.fetch_add(1, std::memory_order_release);
  m_epoch.notify_all();
  for (std::thread& worker : m_workers) worker.join();
}

void ForkJoinPool::runErased(int parts, Function function, const void* context) {
  if (parts < 1 || parts > kMaxParts) {
    throw std::invalid_argument("ForkJoinPool::run: " + std::to_string(parts) +
                                " parts (expected 1 to " + std::to_string(kMaxParts) + ")");
  }
  if (m_workers.empty()) {
    for (int part = 0; part < parts; ++part) function(context, part);
    return;
  }
  m_function = function;
  m_context = context;
  m_done.store(0, std::memory_order_relaxed);
  const std::uint64_t job = m_epoch.load(std::memory_order_relaxed) + 1;
  // Publishes the function, the context and the reset count with the claim word.
  m_claim.store((job << kJobShift) | (static_cast<std::uint64_t>(parts) << kCountShift),
                std::memory_order_release);
  m_epoch.store(job, std::memory_order_release);
  m_epoch.notify_all();
  runClaimedParts(job);
  // Every part is claimed now; wait for those still running on workers.
  for (int spin = 0; spin < kSpinCount; ++spin) {
    if (m_done.load(std::memory_order_acquire) == parts) return;
    relax();
  }
  for (int done = m_done.load(std::memory_order_acquire); done != parts;
       done = m_done.load(std::memory_order_acquire)) {
    m_done.wait(done, std::memory_order_acquire);
  }
}

void ForkJoinPool::runClaimedParts(std::uint64_t job) {
  std::uint64_t word = m_claim.load(std::memory_order_acquire);
  for (;;) {
    if ((word >> kJobShift) != job) return;  // a later run has begun: this one is done
    const auto parts = static_cast<int>((word >> kCountShift) & kFieldMask);
    const auto part = static_cast<int>(word & kFieldMask);
    if (part >= parts) return;
    // A failed exchange reloads `word` and tries again.
    if (m_claim.compare_exchange_weak(word, word + 1, std::memory_order_acq_rel,
                                      std::memory_order_acquire)) {
      // The run cannot finish before this part returns, so its function is still valid.
      m_function(m_context, part);
      if (m_done.fetch_add(1, std::memory_order_acq_rel) + 1 == parts) m_done.notify_one();
      word = m_claim.load(std::memory_order_acquire);
    }
  }
}

void ForkJoinPool::workerLoop() {
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
    runClaimedParts(seen);
  }
}

}  // namespace tissuesim
