// SPDX-License-Identifier: Apache-2.0
#include "mesh/IsolatedCall.h"

#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>

// The sanitizers reserve terabytes of address space for their shadow memory: no RLIMIT_AS there
// (GCC says so with __SANITIZE_*__, clang 14 only through __has_feature).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define TISSUESIM_SANITIZED_ADDRESS_SPACE 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define TISSUESIM_SANITIZED_ADDRESS_SPACE 1
#endif
#endif

#if defined(TISSUESIM_SANITIZED_ADDRESS_SPACE)
#include <sanitizer/common_interface_defs.h>
#endif

namespace tissuesim {
namespace {

/// Writes everything, retrying short writes; false on failure.
bool writeAll(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t written = ::write(fd, data, size);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) return false;
    data += written;
    size -= static_cast<std::size_t>(written);
  }
  return true;
}

/// The child: limits, work, then a status byte ('+' result, '-' error) and the payload.
[[noreturn]] void runChild(int fd, const std::function<std::string()>& work,
                           const IsolationLimits& limits) {
  // A crash ends the child with its signal, whatever handlers the parent installed: a fuzzer's
  // or a sanitizer's handler would otherwise report the library's crash as the parent's own.
  for (const int crash : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT}) ::signal(crash, SIG_DFL);
#if defined(TISSUESIM_SANITIZED_ADDRESS_SPACE)
  // The same for a sanitizer's report on the library's memory error: the child ends with it,
  // and a fuzzer's death callback does not record it as the parent's finding.
  __sanitizer_set_death_callback(nullptr);
#endif
  rlimit cpu{static_cast<rlim_t>(limits.cpuSeconds), static_cast<rlim_t>(limits.cpuSeconds)};
  ::setrlimit(RLIMIT_CPU, &cpu);
#ifndef TISSUESIM_SANITIZED_ADDRESS_SPACE
  rlimit memory{static_cast<rlim_t>(limits.addressSpaceBytes),
                static_cast<rlim_t>(limits.addressSpaceBytes)};
  ::setrlimit(RLIMIT_AS, &memory);
#endif
  std::string message;
  char status = '+';
  try {
    message = work();
  } catch (const std::bad_alloc&) {
    status = '-';
    message = "ran out of memory reading it (more than " +
              std::to_string(limits.addressSpaceBytes >> 20) + " MiB)";
  } catch (const std::exception& error) {
    status = '-';
    message = error.what();
  }
  const bool isSent = writeAll(fd, &status, 1) && writeAll(fd, message.data(), message.size());
  ::_exit(isSent ? 0 : 3);
}

std::string describeEnd(int status, const IsolationLimits& limits, bool isTimedOut) {
  if (isTimedOut) {
    return "reading it did not finish within " + std::to_string(limits.wallTime.count()) +
           " s (stopped)";
  }
  if (WIFSIGNALED(status)) {
    const int signal = WTERMSIG(status);
    if (signal == SIGXCPU) {
      return "reading it took more than " + std::to_string(limits.cpuSeconds) +
             " s of CPU time (stopped)";
    }
    return std::string("the importer crashed on it (") + ::strsignal(signal) + ")";
  }
  return "the importer ended without a result (exit status " + std::to_string(WEXITSTATUS(status)) +
         ")";
}

}  // namespace

IsolatedResult runIsolated(const std::function<std::string()>& work,
                           const IsolationLimits& limits) {
  IsolatedResult result;
  int fds[2];
  if (::pipe(fds) != 0) {
    result.error = std::string("cannot start a reader process: ") + std::strerror(errno);
    return result;
  }
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    result.error = std::string("cannot start a reader process: ") + std::strerror(errno);
    return result;
  }
  if (child == 0) {
    ::close(fds[0]);
    runChild(fds[1], work, limits);
  }
  ::close(fds[1]);
  // Read until the child closes its end, within the wall-clock limit.
  std::string received;
  bool isTimedOut = false;
  const auto deadline = std::chrono::steady_clock::now() + limits.wallTime;
  char buffer[65536];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      isTimedOut = true;
      break;
    }
    pollfd watch{fds[0], POLLIN, 0};
    const int ready = ::poll(&watch, 1, static_cast<int>(left.count()));
    if (ready < 0 && errno == EINTR) continue;
    if (ready == 0) {
      isTimedOut = true;
      break;
    }
    const ssize_t count = ::read(fds[0], buffer, sizeof buffer);
    if (count < 0 && errno == EINTR) continue;
    if (count <= 0) break;  // the child closed its end (finished or died)
    received.append(buffer, static_cast<std::size_t>(count));
  }
  ::close(fds[0]);
  if (isTimedOut) ::kill(child, SIGKILL);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  const bool isCleanExit = !isTimedOut && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (isCleanExit && !received.empty()) {
    result.isOk = received[0] == '+';
    result.isThrown = !result.isOk;
    (result.isOk ? result.bytes : result.error) = received.substr(1);
    return result;
  }
  result.error = describeEnd(status, limits, isTimedOut);
  return result;
}

}  // namespace tissuesim
