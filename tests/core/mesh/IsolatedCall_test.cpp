// SPDX-License-Identifier: Apache-2.0
// Untrusted work in a child process: its result comes back; a throw, a crash, a hang and a
// runaway allocation each come back as one line, and this process goes on.

#include "mesh/IsolatedCall.h"
#include "mesh/IsolatedMeshRead.h"

#include <csignal>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <chrono>
#include <cstdlib>

namespace tissuesim {
namespace {

TEST(IsolatedCall, TheResultComesBack) {
  const IsolatedResult result = runIsolated([] { return std::string("abc\0def", 7); });
  ASSERT_TRUE(result.isOk) << result.error;
  EXPECT_EQ(result.bytes, std::string("abc\0def", 7));
}

TEST(IsolatedCall, AThrowComesBackAsItsMessage) {
  const IsolatedResult result =
      runIsolated([]() -> std::string { throw std::runtime_error("file.stl: bad header"); });
  EXPECT_FALSE(result.isOk);
  EXPECT_TRUE(result.isThrown);
  EXPECT_EQ(result.error, "file.stl: bad header");
}

TEST(IsolatedCall, ACrashIsReportedNotSuffered) {
  const IsolatedResult result = runIsolated([]() -> std::string {
    std::raise(SIGSEGV);
    return "unreachable";
  });
  EXPECT_FALSE(result.isOk);
  EXPECT_FALSE(result.isThrown);
  // "crashed on it (Segmentation fault)"; under AddressSanitizer, whose handler turns the crash
  // into an exit status, "ended without a result".
  EXPECT_NE(result.error.find("the importer"), std::string::npos) << result.error;
}

TEST(IsolatedCall, AHangIsStoppedAtTheWallClockLimit) {
  IsolationLimits limits;
  limits.wallTime = std::chrono::seconds(1);
  const auto start = std::chrono::steady_clock::now();
  const IsolatedResult result = runIsolated(
      []() -> std::string {
        for (;;) std::this_thread::sleep_for(std::chrono::milliseconds(10));
      },
      limits);
  EXPECT_FALSE(result.isOk);
  EXPECT_NE(result.error.find("did not finish within 1 s"), std::string::npos) << result.error;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}

TEST(IsolatedCall, ARunawayAllocationEndsInTheChild) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "no address-space limit under the sanitizers (IsolatedCall.h)";
#endif
  IsolationLimits limits;
  limits.addressSpaceBytes = 1ull << 30;
  const IsolatedResult result = runIsolated(
      [] {
        std::vector<std::vector<char>> hoard;
        for (int i = 0; i < 64; ++i) hoard.emplace_back(std::size_t{256} << 20, 'x');  // 16 GiB
        return std::string("kept ") + std::to_string(hoard.size());
      },
      limits);
  EXPECT_FALSE(result.isOk);
  EXPECT_FALSE(result.error.empty());
}

TEST(IsolatedCall, AReaderLimitFromTheEnvironmentStopsAHangSooner) {
  // The fuzz runs' setting (IsolatedMeshRead.h): one second instead of sixty.
  ::setenv("TISSUESIM_READER_SECONDS", "1", 1);
  const auto start = std::chrono::steady_clock::now();
  try {
    readSurfaceIsolated("slow.stl", []() -> TriangleSurface {
      std::this_thread::sleep_for(std::chrono::seconds(20));
      return {};
    });
    ADD_FAILURE() << "a hung reader returned";
  } catch (const MeshFileError& error) {
    EXPECT_NE(std::string(error.what()).find("slow.stl: reading it did not finish within 1 s"),
              std::string::npos)
        << error.what();
  }
  ::unsetenv("TISSUESIM_READER_SECONDS");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}

}  // namespace
}  // namespace tissuesim
