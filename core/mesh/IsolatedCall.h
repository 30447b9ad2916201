// SPDX-License-Identifier: Apache-2.0
#pragma once
// Running untrusted parsing (assimp on a file from anywhere) in a child process, so that no file
// can crash or hang the program: the child runs the work under limits on its memory and CPU
// time and sends back its result as bytes; a crash, a limit reached or a hang (a wall-clock
// limit, then SIGKILL) becomes one line the caller can show. The parent's state is untouched
// whatever the child does. POSIX (fork, pipe, setrlimit).

#include <chrono>
#include <functional>
#include <string>

namespace tissuesim {

struct IsolationLimits {
  std::chrono::seconds wallTime{60};  ///< the child is killed after this
  int cpuSeconds = 60;                ///< RLIMIT_CPU
  /// RLIMIT_AS (bytes); not applied under AddressSanitizer or ThreadSanitizer, whose shadow
  /// memory needs terabytes of address space.
  unsigned long long addressSpaceBytes = 4ull << 30;
};

struct IsolatedResult {
  bool isOk = false;
  bool isThrown = false;  ///< not ok because work() threw (error: its what())
  std::string bytes;      ///< work()'s result when isOk
  std::string error;      ///< else one line: what work() threw, or how the child ended
};

/// Runs work() in a child process. What it returns comes back in `bytes`; an exception's what()
/// comes back as the error.
IsolatedResult runIsolated(const std::function<std::string()>& work,
                           const IsolationLimits& limits = {});

}  // namespace tissuesim
