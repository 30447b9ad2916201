// SPDX-License-Identifier: Apache-2.0
#include "parallel/ForkJoinPool.h"

#include <atomic>
#include <chrono>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace tissuesim {
namespace {

TEST(ForkJoinPool, RunsEveryPartOnceAndReturnsWhenAllHaveFinished) {
  for (const int threads : {1, 2, 3, 4}) {
    ForkJoinPool pool(threads);
    EXPECT_EQ(pool.threadCount(), threads);
    // Fewer parts than threads, as many, and more.
    for (const int parts : {1, threads, 4, 7}) {
      std::vector<int> counts(static_cast<std::size_t>(parts), 0);
      for (int round = 0; round < 500; ++round) {
        // Each part writes only its own slot; run() returning must make every write visible.
        auto task = [&](int part) { ++counts[static_cast<std::size_t>(part)]; };
        pool.run(parts, task);
        for (int part = 0; part < parts; ++part) {
          ASSERT_EQ(counts[static_cast<std::size_t>(part)], round + 1)
              << threads << " threads, " << parts << " parts, part " << part;
        }
      }
    }
  }
}

TEST(ForkJoinPool, WorkersTakeParts) {
  // Parts long enough that an awake worker claims some before the caller has run them all.
  ForkJoinPool pool(2);
  std::set<std::thread::id> ids;
  for (int round = 0; round < 50 && ids.size() < 2; ++round) {
    std::thread::id partIds[8];
    auto task = [&](int part) {
      partIds[part] = std::this_thread::get_id();
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    };
    pool.run(8, task);
    ids.insert(std::begin(partIds), std::end(partIds));
  }
  EXPECT_EQ(ids.size(), 2u) << "every part ran on one thread in 50 runs";
}

TEST(ForkJoinPool, TheCallerFinishesTheRunWhileAWorkerIsBusyElsewhere) {
  // The first part a worker takes stalls it for 50 ms (as a descheduled thread would be): the
  // caller must run every other part itself rather than leave them to the worker. With parts
  // assigned per thread the worker would run half of them.
  ForkJoinPool pool(2);
  std::atomic<bool> isHeld{false};
  std::vector<std::thread::id> partIds(6);
  const std::thread::id caller = std::this_thread::get_id();
  auto task = [&](int part) {
    partIds[static_cast<std::size_t>(part)] = std::this_thread::get_id();
    if (std::this_thread::get_id() != caller && !isHeld.exchange(true)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the worker is "descheduled"
    }
  };
  pool.run(6, task);
  int onWorker = 0;
  for (const std::thread::id& id : partIds) onWorker += id != caller ? 1 : 0;
  EXPECT_LE(onWorker, 1) << "the caller waited for a stalled worker instead of taking its parts";
}

TEST(ForkJoinPool, WakesAfterSleeping) {
  // Past the spin phase the workers sleep on an atomic wait: a later run must still complete.
  ForkJoinPool pool(2);
  std::atomic<int> sum{0};
  auto task = [&](int part) { sum += part + 1; };
  pool.run(2, task);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  pool.run(2, task);
  EXPECT_EQ(sum.load(), 6);
}

TEST(ForkJoinPool, RefusesZeroThreadsAndBadPartCounts) {
  EXPECT_THROW(ForkJoinPool(0), std::invalid_argument);
  ForkJoinPool pool(2);
  auto task = [](int) {};
  EXPECT_THROW(pool.run(0, task), std::invalid_argument);
  EXPECT_THROW(pool.run(ForkJoinPool::kMaxParts + 1, task), std::invalid_argument);
}

}  // namespace
}  // namespace tissuesim
