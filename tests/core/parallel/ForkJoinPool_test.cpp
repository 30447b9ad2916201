#include "parallel/ForkJoinPool.h"

#include <atomic>
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
    std::vector<int> counts(static_cast<std::size_t>(threads), 0);
    for (int round = 0; round < 2000; ++round) {
      // Each part writes only its own slot; run() returning must make every write visible.
      auto task = [&](int part) { ++counts[static_cast<std::size_t>(part)]; };
      pool.run(task);
      for (int part = 0; part < threads; ++part) {
        ASSERT_EQ(counts[static_cast<std::size_t>(part)], round + 1) << threads << " threads, part " << part;
      }
    }
  }
}

TEST(ForkJoinPool, PartsRunOnDifferentThreads) {
  ForkJoinPool pool(2);
  std::thread::id ids[2];
  auto task = [&](int part) { ids[part] = std::this_thread::get_id(); };
  pool.run(task);
  EXPECT_EQ(ids[0], std::this_thread::get_id());  // part 0 on the caller
  EXPECT_NE(ids[1], ids[0]);
}

TEST(ForkJoinPool, WakesAfterSleeping) {
  // Past the spin phase the workers sleep on an atomic wait: a later run must still wake them.
  ForkJoinPool pool(2);
  std::atomic<int> sum{0};
  auto task = [&](int part) { sum += part + 1; };
  pool.run(task);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  pool.run(task);
  EXPECT_EQ(sum.load(), 6);
}

TEST(ForkJoinPool, RefusesZeroThreads) { EXPECT_THROW(ForkJoinPool(0), std::invalid_argument); }

}  // namespace
}  // namespace tissuesim
